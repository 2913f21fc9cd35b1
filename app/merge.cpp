#include "app/merge.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "app/reproduce.hpp"
#include "parallel/trial_engine.hpp"
#include "results/store.hpp"

namespace fs = std::filesystem;

namespace hyfal::cli {

namespace {

using KeyTuple = std::tuple<std::string, std::string, std::string, std::string, std::string, std::int64_t>;
KeyTuple tuple_of(const TrialKey& k) {
  return {k.experiment, k.suite, k.instance, k.method, k.config, k.trial_index};
}

std::string describe_key(const TrialKey& k) {
  return fmt::format("experiment '{}', suite '{}', method '{}', trial {} (instance {}, config {})", k.experiment,
                     k.suite, k.method, k.trial_index, k.instance, k.config);
}

// A trial present in the merge: OUT's row, or an input's row to be written.
struct Present {
  TrialRecord record;
  std::string source;      // where the row comes from, for messages
  bool stored_in_out = false;
  bool to_write = false;   // an input's row that the merge writes
  bool replaces_out_error = false;
  std::size_t input = 0;   // the input it comes from (to_write)
};

// The first field in which two rows of one key differ that makes them different trials, as
// "FIELD A in HERE vs B in THERE", or "" for the same trial. Times, host, dates and the witness
// path may differ between two runs of the same trial.
std::string differing_field(const TrialRecord& a, const std::string& here, const TrialRecord& b,
                            const std::string& there) {
  const auto differ = [&](const char* field, const auto& x, const auto& y) {
    return fmt::format("{} {} in {} vs {} in {}", field, x, here, y, there);
  };
  if (a.seed != b.seed) return differ("seed", a.seed, b.seed);
  if (a.status != b.status) return differ("status", to_string(a.status), to_string(b.status));
  if (a.nodes != b.nodes) return differ("nodes", a.nodes, b.nodes);
  if (a.propagations != b.propagations) return differ("propagations", a.propagations, b.propagations);
  if (a.integration_steps != b.integration_steps)
    return differ("integration_steps", a.integration_steps, b.integration_steps);
  return "";
}

std::optional<std::string> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return ss.str();
}

// Where a stored witness path points: as stored if absolute; a relative one is looked up from
// the current directory, then from the input database's folder (a database moved together with
// its witness folder). Empty when neither exists.
fs::path locate_witness(const std::string& stored, const std::string& database) {
  std::error_code ec;
  const fs::path p(stored);
  if (fs::is_regular_file(p, ec)) return p;
  if (p.is_absolute()) return {};
  const fs::path beside = fs::absolute(database, ec).parent_path() / p;
  if (fs::is_regular_file(beside, ec)) return beside;
  return {};
}

}  // namespace

int cmd_merge(const MergeArgs& a) {
  check_output_path(a.out, "OUT");
  if (!a.witness_dir.empty()) {
    check_output_path(a.witness_dir, "--witness-dir");
    check_directory_creatable(a.witness_dir, "--witness-dir");
  }
  std::error_code ec;
  const bool out_exists = fs::exists(a.out, ec);
  if (!out_exists) {
    const fs::path parent = fs::path(a.out).parent_path();
    check_directory_creatable(parent.empty() ? "." : parent.string(), "OUT");
  }
  for (const std::string& in : a.inputs) {
    check_output_path(in, "input");
    if (out_exists && fs::equivalent(a.out, in, ec))
      throw UsageError(fmt::format("merge: OUT '{}' is also an input ('{}'); write the merge to a new file", a.out, in));
  }

  // 1. Read everything: OUT's rows (read-only; a new or empty OUT holds none), then each input.
  std::map<KeyTuple, Present> present;
  if (out_exists && !(fs::is_regular_file(a.out, ec) && fs::file_size(a.out, ec) == 0)) {
    TrialStore out = TrialStore::open_read_only(a.out);
    for (TrialRecord& r : out.load()) {
      const KeyTuple key = tuple_of(r.key);
      present[key] = Present{std::move(r), fmt::format("OUT '{}'", a.out), true};
    }
  }
  std::size_t input_rows = 0;
  for (std::size_t i = 0; i < a.inputs.size(); ++i) {
    const std::string& in = a.inputs[i];
    std::vector<TrialRecord> rows = TrialStore::open_read_only(in).load_with_series();
    input_rows += rows.size();
    for (TrialRecord& r : rows) {
      auto [at, added] = present.try_emplace(tuple_of(r.key));
      Present& p = at->second;
      if (added) {
        p = Present{std::move(r), fmt::format("'{}'", in), false, true, false, i};
        continue;
      }
      const std::string here = fmt::format("'{}'", in);
      if (p.record.seed != r.seed)
        throw UsageError(fmt::format("merge: '{}' conflicts with {} at {}: {}; nothing was merged", in, p.source,
                                     describe_key(r.key), differing_field(r, here, p.record, p.source)));
      if (p.record.status == TrialStatus::error && r.status != TrialStatus::error) {
        // As on resume: a result replaces an attempt that ended in error, its series with it.
        const bool replaces_out_error = p.stored_in_out || p.replaces_out_error;
        p = Present{std::move(r), here, false, true, replaces_out_error, i};
        continue;
      }
      if (r.status == TrialStatus::error) continue;  // an error row gives way to what is there
      const std::string field = differing_field(r, here, p.record, p.source);
      if (!field.empty())
        throw UsageError(fmt::format("merge: '{}' conflicts with {} at {}: {}; nothing was merged", in, p.source,
                                     describe_key(r.key), field));
      // The same trial: skipped.
    }
  }

  std::vector<TrialRecord> to_write;
  std::vector<std::size_t> input_of;
  std::size_t replaced = 0;
  for (auto& [key, p] : present)
    if (p.to_write) {
      replaced += p.replaces_out_error;
      input_of.push_back(p.input);
      to_write.push_back(std::move(p.record));
    }

  // 2. Witnesses: kept where they are, or copied into --witness-dir (all found before writing).
  struct Copy {
    fs::path from, to;
  };
  std::vector<Copy> copies;
  std::size_t missing = 0;
  for (std::size_t k = 0; k < to_write.size(); ++k) {
    TrialRecord& r = to_write[k];
    if (r.witness.empty()) continue;
    if (a.witness_dir.empty()) {
      missing += !fs::is_regular_file(r.witness, ec);
      continue;
    }
    const std::string& database = a.inputs[input_of[k]];
    const fs::path from = locate_witness(r.witness, database);
    if (from.empty())
      throw UsageError(fmt::format("merge: the witness '{}' of {} in '{}' is missing (looked relative to the current "
                                   "directory and to the database's folder); nothing was merged",
                                   r.witness, describe_key(r.key), database));
    const fs::path to = witness_path(a.witness_dir, r.key);
    r.witness = to.string();
    if (fs::exists(to, ec)) {
      if (fs::equivalent(from, to, ec)) continue;  // already in place
      if (read_bytes(to) != read_bytes(from))
        throw UsageError(fmt::format("merge: '{}' already exists with other content than the witness '{}' of {}; "
                                     "nothing was merged",
                                     to.string(), from.string(), describe_key(r.key)));
      continue;  // the same bytes are there already
    }
    copies.push_back({from, to});
  }

  // 3. Write: the copies (each atomic), then OUT (created if missing) with every row in one
  // transaction; a failure removes the copies again, so the witness folder and OUT stay as they
  // were (a failed copy happens before OUT is created).
  std::vector<fs::path> made;
  try {
    for (const Copy& c : copies) {
      const auto bytes = read_bytes(c.from);
      if (!bytes) throw EnvironmentError(fmt::format("cannot read witness '{}'", c.from.string()));
      write_file_atomic(c.to.string(), *bytes);
      made.push_back(c.to);
    }
    TrialStore out = TrialStore::open(a.out);
    if (!to_write.empty()) out.insert_all(to_write);
  } catch (...) {
    for (const fs::path& p : made) fs::remove(p, ec);
    throw;
  }
  fmt::print("merged {} trials into {} ({} new, {} replacing error rows); {} skipped as already present; "
             "{} witnesses copied\n",
             to_write.size(), a.out, to_write.size() - replaced, replaced, input_rows - to_write.size(),
             copies.size());
  if (missing > 0)
    fmt::print(stderr,
               "[hyfal] warning: {} witness files of the merged trials do not exist at their stored paths (relative "
               "paths are read from the current directory); --witness-dir DIR copies them, looking beside each input "
               "database too\n",
               missing);
  return 0;
}

}  // namespace hyfal::cli
