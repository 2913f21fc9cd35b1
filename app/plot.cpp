#include "app/plot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <vector>

#include <fmt/format.h>

#include "app/runner.hpp"
#include "core/witness/witness.hpp"

extern char** environ;

#ifndef HYFAL_SOURCE_DIR
#define HYFAL_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;

namespace hyfal::cli {

namespace {

constexpr const char* kInstallHint = "install python3 and python3-matplotlib (scripts/setup.sh installs them)";

// Debian's interpreter, the one apt's python3-matplotlib is installed for (a virtual environment's
// packages are not what scripts/setup.sh manages); HYFAL_PYTHON names another.
std::string python_interpreter() {
  const char* python = std::getenv("HYFAL_PYTHON");
  return python && *python ? python : "/usr/bin/python3";
}

fs::path this_executable() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe;
}

// scripts/<name> of the source tree this binary was built from, else of the tree around the
// build folder the binary is in (<root>/build/app/hyfal: a source tree moved after the build).
// Empty when neither exists; looked_in then lists where it looked.
std::string find_script(const std::string& name, std::string& looked_in) {
  std::vector<fs::path> candidates{fs::path(HYFAL_SOURCE_DIR) / "scripts" / name};
  if (const fs::path exe = this_executable(); !exe.empty())
    candidates.push_back(exe.parent_path().parent_path().parent_path() / "scripts" / name);
  looked_in.clear();
  for (const fs::path& candidate : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) return candidate.string();
    looked_in += (looked_in.empty() ? "" : ", ") + candidate.string();
  }
  return {};
}

struct ProgramRun {
  int exit_code = -1;       // the exit status (128 + signal); -1 when it did not start
  std::string start_error;  // why it did not start
  std::string output;       // stdout and stderr together, when captured
};

// Runs argv (argv[0] looked up on PATH unless it holds a '/'); with capture its stdout and
// stderr are collected, else they are this process's. posix_spawn: safe with threads running.
ProgramRun run_program(const std::vector<std::string>& argv, bool capture) {
  ProgramRun run;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int pipe_fds[2] = {-1, -1};
  if (capture && pipe2(pipe_fds, O_CLOEXEC) != 0) {
    run.start_error = std::strerror(errno);
    return run;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (capture) {
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  }
  std::fflush(nullptr);
  std::cout.flush();
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (capture) close(pipe_fds[1]);
  if (rc != 0) {
    if (capture) close(pipe_fds[0]);
    run.start_error = std::strerror(rc);
    return run;
  }
  if (capture) {
    char buffer[4096];
    for (;;) {
      const ssize_t got = read(pipe_fds[0], buffer, sizeof buffer);
      if (got > 0) {
        run.output.append(buffer, static_cast<std::size_t>(got));
      } else if (got == 0 || errno != EINTR) {
        break;
      }
    }
    close(pipe_fds[0]);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

// The interpreter running a script: -B, so that importing plot_tables from plot_witness leaves
// no __pycache__ in the source tree.
std::vector<std::string> script_command(const std::string& script) { return {python_interpreter(), "-B", script}; }

std::string last_line(const std::string& text) {
  std::size_t end = text.find_last_not_of("\r\n");
  if (end == std::string::npos) return "(no message)";
  const std::size_t begin = text.rfind('\n', end);
  return text.substr(begin == std::string::npos ? 0 : begin + 1, end + 1 - (begin == std::string::npos ? 0 : begin + 1));
}

}  // namespace

int cmd_plot(const PlotArgs& a) {
  // Everything is checked before the script runs, so that a bad argument writes nothing.
  if (a.tables_dir.empty() == a.witness.empty())
    throw UsageError(a.witness.empty() ? "give a tables folder (hyfal plot TABLES_DIR) or --witness FILE"
                                       : "give a tables folder or --witness FILE, not both");
  std::string script_name = "plot_tables.py", out = a.out;
  if (!a.tree.empty() && a.witness.empty()) throw UsageError("--tree goes with --witness (the tree drawn under its path)");
  if (!a.witness.empty()) {
    script_name = "plot_witness.py";
    try {
      (void)witness_from_text(read_input_file(a.witness));
    } catch (const WitnessError& e) {
      throw UsageError(one_line(fmt::format("--witness '{}': {}", a.witness, e.what())));
    }
    if (!a.tree.empty()) {
      std::error_code ec;
      if (!fs::is_regular_file(a.tree, ec) || access(a.tree.c_str(), R_OK) != 0)
        throw UsageError(one_line(fmt::format("--tree '{}': not a readable file", a.tree)));
    }
    if (!a.out_given) out = fs::path(a.witness).replace_extension(".png").string();
    check_output_path(out, "--out");
    if (fs::path(out).extension() != ".png" || fs::path(out).stem().empty())
      throw UsageError(fmt::format("--out '{}': expected a file name ending in .png (the .svg goes beside it)", out));
    if (fs::is_directory(out)) throw UsageError(fmt::format("--out '{}' is a directory", out));
    const fs::path parent = fs::path(out).parent_path();
    check_directory_creatable(parent.empty() ? "." : parent.string(), "--out");
  } else {
    std::error_code ec;
    if (!fs::is_directory(a.tables_dir, ec))
      throw UsageError(fmt::format("tables folder '{}': no such folder", a.tables_dir));
    if (a.out_given) {
      check_output_path(out, "--out");
      check_directory_creatable(out, "--out");
    }
  }

  std::string looked_in;
  const std::string script = find_script(script_name, looked_in);
  if (script.empty()) {
    fmt::print(stderr, "hyfal: error: scripts/{} not found (looked in {}): hyfal plot runs it from hyfal's source tree\n",
               script_name, looked_in);
    return 3;
  }
  std::vector<std::string> command = script_command(script);
  if (!a.witness.empty()) {
    command.push_back(a.witness);
    if (const fs::path exe = this_executable(); !exe.empty()) {
      command.push_back("--hyfal");  // for `hyfal instance export` (the maze, the aircraft)
      command.push_back(exe.string());
    }
  } else {
    command.push_back(a.tables_dir);
  }
  if (!out.empty()) {
    command.push_back("--out");
    command.push_back(out);
  }
  if (!a.tree.empty()) {
    command.push_back("--tree");
    command.push_back(a.tree);
  }
  const ProgramRun run = run_program(command, false);
  if (run.exit_code < 0) {
    fmt::print(stderr, "hyfal: error: cannot run {} ({}): {}\n", command[0], run.start_error, kInstallHint);
    return 3;
  }
  if (run.exit_code == 0 || run.exit_code == 2 || run.exit_code == 3) return run.exit_code;  // the script said why
  fmt::print(stderr, "hyfal: error: {} ended with exit code {}\n", script, run.exit_code);
  return 3;
}

void write_table_figures(const std::string& out_dir, const std::string& id) {
  try {
    std::string looked_in;
    const std::string script = find_script("plot_tables.py", looked_in);
    if (script.empty()) {
      fmt::print(stderr, "[hyfal] no figures: scripts/plot_tables.py not found (looked in {})\n", looked_in);
      return;
    }
    std::vector<std::string> command = script_command(script);
    command.insert(command.end(), {out_dir, "--only", id});
    const ProgramRun run = run_program(command, true);
    if (run.exit_code < 0) {
      fmt::print(stderr, "[hyfal] no figures: cannot run {} ({}): {}\n", command[0], run.start_error, kInstallHint);
      return;
    }
    if (run.exit_code != 0) {
      fmt::print(stderr, "[hyfal] no figures ({})\n", one_line(last_line(run.output)));
      return;
    }
    std::string pngs;
    std::size_t count = 0;
    for (std::size_t begin = 0; begin < run.output.size();) {
      std::size_t end = run.output.find('\n', begin);
      if (end == std::string::npos) end = run.output.size();
      const std::string line = run.output.substr(begin, end - begin);
      if (line.size() > 4 && line.compare(line.size() - 4, 4, ".png") == 0) {
        pngs += (count++ ? ", " : "") + line;
      }
      begin = end + 1;
    }
    if (count > 0) fmt::print(stderr, "[hyfal] figures: {} (and .svg)\n", pngs);
  } catch (const std::exception& e) {  // a figure never fails the reproduce
    fmt::print(stderr, "[hyfal] no figures ({})\n", e.what());
  }
}

}  // namespace hyfal::cli
