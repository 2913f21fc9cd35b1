// What the end-to-end tests of the hyfal binary share (test_cli, test_shard_merge, test_mpi):
// quoting for sh, files, the binary run as a child process with caps, and the sqlite3 tool.
// Each test file includes it once, inside its own unnamed namespace.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <iostream>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#ifndef HYFAL_BIN
#error "HYFAL_BIN (the path of the built hyfal binary) must be defined"
#endif

namespace hyfal_cli_test {

namespace fs = std::filesystem;
using Args = std::vector<std::string>;

inline std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

inline std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
}

inline std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      parts.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  parts.push_back(cur);
  return parts;
}

inline bool contains(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }

// The regular files under root (none if it does not exist), sorted: what a command created.
inline std::vector<fs::path> files_under(const fs::path& root) {
  std::vector<fs::path> v;
  if (!fs::exists(root)) return v;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) v.push_back(e.path());
  std::sort(v.begin(), v.end());
  return v;
}

// Lines of a text, without the empty piece after a final newline.
inline std::vector<std::string> lines(const std::string& s) {
  auto v = split(s, '\n');
  if (!v.empty() && v.back().empty()) v.pop_back();
  return v;
}

inline int decode_status(int status) {
  if (status == -1) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

struct Result {
  int code = -1;
  std::string out, err, command;
};

inline std::ostream& operator<<(std::ostream& os, const Result& r) {
  return os << "command: " << r.command << "\nexit: " << r.code << "\nstdout:\n"
            << r.out << "\nstderr:\n"
            << r.err;
}

// Runs hyfal with args in cwd; stdout and stderr go to files under io_dir (never under cwd, so
// that cwd can be checked for files hyfal created). A memory cap and a wall-clock cap keep a
// misbehaving binary from taking the machine down with it (exit 137 when the cap is hit).
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr const char* kMemoryCap = "";  // sanitizers reserve terabytes of shadow address space
constexpr int kSlowdown = 4;            // TSan runs a 200-trial resume ~15x slower than Release
#else
constexpr const char* kMemoryCap = "ulimit -v 8388608 && ";
constexpr int kSlowdown = 1;
#endif

// launcher (ending in a space) runs before the binary, e.g. to drop privileges; binary: another
// hyfal build than the one under test (an older one, to show a defect).
inline Result run_hyfal(const fs::path& cwd, const fs::path& io_dir, const Args& args, int time_cap_s = 120,
                        const std::string& launcher = "", const std::string& binary = HYFAL_BIN) {
  static std::atomic<int> counter{0};
  fs::create_directories(io_dir);
  const int n = counter++;
  const fs::path out = io_dir / ("cmd" + std::to_string(n) + ".out");
  const fs::path err = io_dir / ("cmd" + std::to_string(n) + ".err");
  std::string cmd = "cd ";
  cmd += quote(cwd.string());
  cmd += " && ";
  cmd += kMemoryCap;
  cmd += "exec ";
  cmd += launcher;
  cmd += "timeout -s KILL ";
  cmd += std::to_string(time_cap_s * kSlowdown);  // a safety net, not a speed assertion
  cmd += ' ';
  cmd += quote(binary);
  for (const auto& a : args) {
    cmd += ' ';
    cmd += quote(a);
  }
  cmd += " >";
  cmd += quote(out.string());
  cmd += " 2>";
  cmd += quote(err.string());
  cmd += " </dev/null";
  Result r;
  r.code = decode_status(std::system(cmd.c_str()));
  r.out = read_text(out);
  r.err = read_text(err);
  r.command = "hyfal";
  for (const auto& a : args) r.command += " " + a;
  return r;
}

// Runs the sqlite3 command-line tool on db; returns its rows (fields split at '|').
// Sets ok to false (and leaves the output in error) when sqlite3 fails.
struct SqlResult {
  bool ok = false;
  std::vector<std::vector<std::string>> rows;
  std::string text;
};

inline SqlResult sql(const fs::path& db, const std::string& query) {
  SqlResult r;
  const std::string cmd =
      "sqlite3 -batch -noheader -separator '|' " + quote(db.string()) + " " + quote(query) + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t got;
  while ((got = fread(buf, 1, sizeof buf, p)) > 0) r.text.append(buf, got);
  r.ok = decode_status(pclose(p)) == 0;
  for (const auto& line : lines(r.text)) r.rows.push_back(split(line, '|'));
  return r;
}

// A fresh folder per test: root/work is where hyfal runs, root/io holds its captured output. A
// failed test keeps its folder for inspection. `prefix` names the test file in the folder's name.
class HyfalBinaryTest : public ::testing::Test {
 protected:
  explicit HyfalBinaryTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name)
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    root_ = fs::temp_directory_path() / ("hyfal_" + prefix_ + "_" + name + "_" + std::to_string(getpid()));
    fs::remove_all(root_);
    fs::create_directories(work());
    fs::create_directories(io());
  }
  void TearDown() override {
    if (HasFailure())
      std::cerr << "[test_" << prefix_ << "] kept " << root_ << " for inspection\n";
    else
      fs::remove_all(root_);
  }

  fs::path work() const { return root_ / "work"; }
  fs::path io() const { return root_ / "io"; }
  Result hyfal(const Args& args, int time_cap_s = 120) { return run_hyfal(work(), io(), args, time_cap_s); }

  std::string prefix_;
  fs::path root_;
};

}  // namespace hyfal_cli_test
