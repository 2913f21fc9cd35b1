// A seeded mutation fuzzer for hyfal's two parsers of outside text, run for a fixed budget (a
// fixed number of inputs, a few seconds in Release; also under ASan/UBSan, scripts/sanitize.sh):
//
//  (a) witness files: witness_from_text + validate_witness on the suite the witness names,
//      starting from the committed corpus tests/fuzz_corpus/*.json (real witnesses of small
//      instances, made with `hyfal run --suite S --method M --trials 1 --witness-dir D`, e.g.
//      thermostat/rrt, example31/rrt, navigation n=2/hydice and n=4/rrt, aircraft
//      esposito5/rrft; nnx-cmaes-sparse: NNx at horizon 3 by CMA-ES, its states left out where
//      the input holds, validated by replay); mutations: bytes, number tokens (huge, negative, NaN text, 1e999),
//      deleted members, swapped types, truncated and duplicated arrays, random modes,
//      transitions and durations. Plus synthetic witnesses for every suite (its default
//      instance), so that every model's valid_mode is exercised.
//  (b) settings: resolve_options / parse_option_value against every suite's parameters and every
//      method's options with random key=value texts; then the suite's make (small instances only)
//      and the method's make.
//  (c) table and experiment files (TOML): load_paper_table / load_experiment_file on mutations of
//      the committed experiments/paper/*.toml and experiments/example.toml (bytes, TOML values,
//      deleted and duplicated lines, keys renamed); only ExperimentFileError, in one line.
//
// The property: no crash, no undefined behaviour, no hang, and no exception but the documented
// ones (WitnessError from the witness parser, OptionError / std::invalid_argument from settings
// and makes); every error message is one line; a validation returns in bounded time; a mode
// that no suite has is always reported as malformed.
//
// HYFAL_FUZZ_ITERATIONS scales the budget (e.g. 20 for twenty times the default inputs) and
// HYFAL_FUZZ_SEED changes the seed, for longer runs by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "app/experiment_file.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/method_entry.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/registry.hpp"

#ifndef HYFAL_FUZZ_CORPUS
#error "HYFAL_FUZZ_CORPUS (the folder of the witness corpus) must be defined"
#endif

namespace hyfal {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::uint64_t fuzz_seed() {
  const char* s = std::getenv("HYFAL_FUZZ_SEED");
  return s ? std::strtoull(s, nullptr, 10) : 20240611ULL;
}

int budget(int inputs) {
  const char* s = std::getenv("HYFAL_FUZZ_ITERATIONS");
  const long scale = s ? std::strtol(s, nullptr, 10) : 1;
  return static_cast<int>(std::max(1L, scale) * inputs);
}

// A deterministic random source with the few draws the mutators need.
struct Dice {
  std::mt19937_64 g;
  explicit Dice(std::uint64_t seed) : g(seed) {}
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(g() % n); }
  bool chance(double p) { return std::uniform_real_distribution<double>(0.0, 1.0)(g) < p; }
  template <class T>
  const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }
};

// Number texts at the edges: of double, of the integer types, of JSON's grammar, and NaN / inf
// spellings JSON does not have.
const std::vector<std::string> kNumberTexts = {
    "0", "-0", "1", "-1", "2", "3", "4", "5", "7", "17", "0.5", "-1.5", "1e-320", "1e-300", "1e300", "-1e300",
    "1e999", "-1e999", "1.7976931348623157e308", "2147483647", "2147483648", "-2147483649", "4294967296",
    "9007199254740993", "9223372036854775807", "9223372036854775808", "-9223372036854775809",
    "18446744073709551615", "18446744073709551616", "1e12", "1e15", "1e30", "NaN", "nan", "Infinity",
    "-Infinity", "0x10", "1e", "--1", ".5", "5.", "1e+", "00", "-"};

// Other JSON values: every type, empty and odd strings (a NUL, a newline, a lone surrogate).
const std::vector<std::string> kValueTexts = {"null", "true", "false", "\"\"", "\"x\"", "\"\\u0000\"",
                                              "\"\\n\"", "[]", "{}", "[1,2,3]", "{\"a\":1}", "\"\\ud800\"",
                                              "\"thermostat\"", "[[[[[]]]]]", "-1", "1e999"};

// The corpus: each witness with the system of its instance (built once).
struct Seed {
  std::string name, text;
  Json json;
  Witness witness;
  std::shared_ptr<const System> system;
};

const std::vector<Seed>& corpus() {
  static const std::vector<Seed> seeds = [] {
    std::vector<Seed> v;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(HYFAL_FUZZ_CORPUS))
      if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      std::ifstream in(f, std::ios::binary);
      std::ostringstream ss;
      ss << in.rdbuf();
      Seed s;
      s.name = f.filename().string();
      s.text = ss.str();
      s.json = Json::parse(s.text);
      s.witness = witness_from_text(s.text);
      const SuiteEntry* suite = find_suite(s.witness.suite);
      if (!suite) throw std::runtime_error("corpus: unknown suite in " + s.name);
      std::vector<std::pair<std::string, std::string>> sets;
      for (const auto& [k, val] : s.witness.instance.items())
        sets.emplace_back(k, val.is_string() ? val.get<std::string>() : val.dump());
      s.system = suite->make(resolve_options(suite->parameters, sets));
      v.push_back(std::move(s));
    }
    return v;
  }();
  return seeds;
}

// ---------------------------------------------------------------------------------------------
// Mutators

// Spans of number tokens outside strings (an approximate JSON scan, good enough to aim at).
std::vector<std::pair<std::size_t, std::size_t>> number_spans(const std::string& t) {
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  bool in_string = false;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const char c = t[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      std::size_t j = i + 1;
      while (j < t.size() && std::string_view("0123456789.eE+-").find(t[j]) != std::string_view::npos) ++j;
      spans.emplace_back(i, j - i);
      i = j - 1;
    }
  }
  return spans;
}

void mutate_bytes(std::string& t, Dice& d) {
  if (t.empty()) {
    t = d.pick(kValueTexts);
    return;
  }
  static const std::string kSignificant = "{}[]\",:0123456789eE.-+ \n\\tfn";
  const std::size_t i = d.below(t.size());
  switch (d.below(7)) {
    case 0: t[i] = static_cast<char>(t[i] ^ (1 << d.below(8))); break;
    case 1: t[i] = kSignificant[d.below(kSignificant.size())]; break;
    case 2: t.erase(i, 1 + d.below(16)); break;
    case 3: t.insert(i, t.substr(i, 1 + d.below(64))); break;
    case 4: t.resize(i); break;
    case 5: t.insert(i, d.pick(kValueTexts)); break;
    default: {
      const auto spans = number_spans(t);
      if (spans.empty()) break;
      const auto [at, len] = spans[d.below(spans.size())];
      t.replace(at, len, d.pick(kNumberTexts));
    }
  }
}

// Every node of j with its parent (nullptr for the root) and its key or index in the parent.
struct Node {
  Json* node;
  Json* parent;
  std::string key;
  std::size_t index;
};
void collect(Json& j, Json* parent, const std::string& key, std::size_t index, std::vector<Node>& out) {
  out.push_back({&j, parent, key, index});
  if (j.is_object())
    for (auto& [k, v] : j.items()) collect(v, &j, k, 0, out);
  else if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) collect(j[i], &j, "", i, out);
}

Json random_value(Dice& d) {
  for (int tries = 0; tries < 8; ++tries) {
    const std::string& t = d.chance(0.6) ? d.pick(kNumberTexts) : d.pick(kValueTexts);
    try {
      return Json::parse(t);
    } catch (const Json::exception&) {  // not JSON (NaN, 1e999, ...): the byte mutator uses those
    }
  }
  return Json(d.g());  // a random 64-bit unsigned
}

void mutate_tree(Json& root, Dice& d) {
  // Aimed at the fields the validator indexes with, half of the time.
  if (d.chance(0.5) && root.is_object() && root.contains("pieces") && root["pieces"].is_array() &&
      !root["pieces"].empty()) {
    Json& piece = root["pieces"][d.below(root["pieces"].size())];
    if (!piece.is_object()) return;
    switch (d.below(5)) {
      case 0: piece["mode"] = d.chance(0.5) ? Json(d.g()) : Json(d.below(64)); return;
      case 1: piece["transition"] = static_cast<std::int64_t>(d.below(80)) - 2; return;
      case 2: piece["duration"] = d.chance(0.5) ? Json(1e300) : Json(std::ldexp(1.0, static_cast<int>(d.below(60)) - 30)); return;
      default: {
        Json& end = root[d.chance(0.5) ? "final" : "initial"];
        if (end.is_object()) end["mode"] = d.chance(0.5) ? Json(d.g()) : Json(d.below(64));
        return;
      }
    }
  }
  std::vector<Node> nodes;
  collect(root, nullptr, "", 0, nodes);
  const Node& n = nodes[d.below(nodes.size())];
  switch (d.below(6)) {
    case 0:  // replace by another value (any type)
      *n.node = random_value(d);
      break;
    case 1:  // delete
      if (n.parent && n.parent->is_object())
        n.parent->erase(n.key);
      else if (n.parent && n.parent->is_array())
        n.parent->erase(n.index);
      break;
    case 2:  // truncate an array
      if (n.node->is_array() && !n.node->empty()) n.node->erase(n.node->begin() + static_cast<std::ptrdiff_t>(d.below(n.node->size())), n.node->end());
      break;
    case 3:  // duplicate an array element
      if (n.node->is_array() && !n.node->empty()) {
        const Json copy = (*n.node)[d.below(n.node->size())];  // (not a reference into the array it grows)
        n.node->insert(n.node->begin(), copy);
      }
      break;
    case 4:  // swap the type, keeping the content
      if (n.node->is_number())
        *n.node = n.node->dump();
      else if (n.node->is_string())
        *n.node = Json::array({*n.node});
      else if (n.node->is_array())
        *n.node = Json{{"0", *n.node}};
      else
        *n.node = Json::array();
      break;
    default:  // a member added to an object
      if (n.node->is_object()) (*n.node)[d.chance(0.5) ? "mode" : "extra"] = random_value(d);
  }
}

// ---------------------------------------------------------------------------------------------
// The property for one witness text

struct WitnessStats {
  int inputs = 0, parse_errors = 0, other_instance = 0, valid = 0, invalid = 0, malformed = 0;
  double slowest_s = 0.0;
};

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

// A JSON value for a failure message (invalid UTF-8 replaced, not thrown on).
std::string show(const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); }

void check_witness_text(const std::string& text, WitnessStats& st, const std::string& context) {
  ++st.inputs;
  Witness w;
  try {
    w = witness_from_text(text);
  } catch (const WitnessError& e) {
    ++st.parse_errors;
    EXPECT_TRUE(one_line(e.what())) << context << ": " << e.what();
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << context << ": witness_from_text threw a " << typeid(e).name() << ": " << e.what();
    return;
  }
  const Seed* seed = nullptr;
  for (const auto& s : corpus())
    if (s.witness.suite == w.suite && s.witness.instance == w.instance) seed = &s;
  if (!seed) {  // the instance was mutated: resolve it (make is fuzzed by the settings test)
    ++st.other_instance;
    if (const SuiteEntry* suite = find_suite(w.suite)) {
      std::vector<std::pair<std::string, std::string>> sets;
      for (const auto& [k, v] : w.instance.items()) sets.emplace_back(k, v.is_string() ? v.get<std::string>() : v.dump());
      try {
        (void)resolve_options(suite->parameters, sets);
      } catch (const OptionError&) {
      } catch (const std::exception& e) {
        ADD_FAILURE() << context << ": resolve_options threw a " << typeid(e).name() << ": " << e.what();
      }
    }
    return;
  }
  const auto t0 = Clock::now();
  ValidationReport r;
  try {
    r = validate_witness(*seed->system, w);
  } catch (const std::exception& e) {
    ADD_FAILURE() << context << ": validate_witness threw a " << typeid(e).name() << ": " << e.what();
    return;
  }
  st.slowest_s = std::max(st.slowest_s, std::chrono::duration<double>(Clock::now() - t0).count());
  EXPECT_TRUE(one_line(r.reason)) << context << ": " << r.reason;
  EXPECT_FALSE(r.valid && r.malformed) << context;
  if (r.valid) {
    ++st.valid;
    // A valid witness stays valid through its own JSON (what hyfal writes, it reads back).
    EXPECT_TRUE(validate_witness(*seed->system, witness_from_json(to_json(w))).valid) << context;
  } else {
    ++(r.malformed ? st.malformed : st.invalid);
  }
}

// Every corpus witness validates: mutations start from real, valid witnesses. (When a model
// change makes one invalid, regenerate it as described at the top of this file.)
TEST(FuzzWitness, CorpusWitnessesValidate) {
  ASSERT_GE(corpus().size(), 3u) << HYFAL_FUZZ_CORPUS;
  for (const auto& s : corpus()) {
    const ValidationReport r = validate_witness(*s.system, s.witness);
    EXPECT_TRUE(r.valid) << s.name << ": " << r.reason;
  }
}

TEST(FuzzWitness, MutatedCorpusNeverCrashesAndOnlyThrowsWitnessError) {
  Dice d(fuzz_seed());
  WitnessStats st;
  const int n = budget(1500);
  for (int i = 0; i < n; ++i) {
    const Seed& s = corpus()[d.below(corpus().size())];
    std::string text;
    if (d.chance(0.6)) {  // structured edits, then maybe bytes
      Json j = s.json;
      const std::size_t edits = 1 + d.below(3);
      for (std::size_t e = 0; e < edits; ++e) mutate_tree(j, d);
      text = j.dump(d.chance(0.5) ? 1 : -1);
      if (d.chance(0.3)) mutate_bytes(text, d);
    } else {
      text = s.text;
      const std::size_t edits = 1 + d.below(4);
      for (std::size_t e = 0; e < edits; ++e) mutate_bytes(text, d);
    }
    check_witness_text(text, st, "input " + std::to_string(i) + " (from " + s.name + ", HYFAL_FUZZ_SEED=" +
                                     std::to_string(fuzz_seed()) + ")");
    if (HasFailure()) break;  // one reproducible report, not a flood
  }
  // The budget reached every outcome (else the mutators aim badly).
  EXPECT_GT(st.parse_errors, 0);
  EXPECT_GT(st.malformed, 0);
  EXPECT_GT(st.invalid, 0);
  EXPECT_LT(st.slowest_s, 30.0) << "a validation must return in bounded time";
  std::printf("[fuzz] %d witness inputs: %d parse errors, %d other instances, %d valid, %d invalid, %d malformed; "
              "slowest validation %.3f s\n",
              st.inputs, st.parse_errors, st.other_instance, st.valid, st.invalid, st.malformed, st.slowest_s);
}

// Synthetic witnesses for every suite's default instance: the start of the system with random
// pieces whose modes, transitions, durations and inputs range from plausible to absurd.
TEST(FuzzWitness, SyntheticWitnessesForEverySuite) {
  Dice d(fuzz_seed() ^ 0x5eedULL);
  const int per_suite = budget(60);
  for (const SuiteEntry& suite : all_suites()) {
    SCOPED_TRACE(suite.name);
    const auto sys = suite.make(resolve_options(suite.parameters, {}));
    const SystemInfo& info = sys->info();
    const auto random_mode = [&]() -> Mode {
      switch (d.below(4)) {
        case 0: return info.initial_mode;
        case 1: return d.below(40);
        case 2: return Mode{1} << (40 + d.below(24));  // beyond every suite's modes (navigation <= 2^24)
        default: return d.g();
      }
    };
    for (int i = 0; i < per_suite; ++i) {
      Witness w = make_witness(*sys, "fuzz", i, {});
      Trajectory& t = w.trajectory;
      t.parameters = info.parameters;
      t.initial_mode = d.chance(0.8) ? info.initial_mode : random_mode();
      t.initial_x = info.initial_state;
      std::vector<double> x = info.initial_state;
      Mode q = t.initial_mode;
      const std::size_t pieces = d.below(4);
      for (std::size_t k = 0; k < pieces; ++k) {
        TrajectoryPiece p;
        p.mode = d.chance(0.7) ? q : random_mode();
        const Box& box = sys->inputs(info.initial_mode).box;
        for (std::size_t c = 0; c < box.dim(); ++c)
          p.u.push_back(d.chance(0.9) ? box.lo[c] + (box.hi[c] - box.lo[c]) * std::ldexp(static_cast<double>(d.below(1024)), -10)
                                      : 1e6);
        const double durations[] = {0.0, info.step_duration / 3, info.step_duration, info.step_duration * (1 + 1e-12),
                                    info.step_duration * 2, 1e300};
        p.duration = durations[d.below(6)];
        p.transition = static_cast<int>(d.below(8)) - 2;
        p.x_start = x;
        p.x_end = x;
        t.pieces.push_back(std::move(p));
        q = t.pieces.back().mode;
      }
      t.final_mode = d.chance(0.7) ? q : random_mode();
      t.final_x = x;
      t.final_spec = 0.0;
      bool absurd_mode = t.initial_mode >= (Mode{1} << 40) || t.final_mode >= (Mode{1} << 40);
      for (const auto& p : t.pieces) absurd_mode = absurd_mode || p.mode >= (Mode{1} << 40);
      ValidationReport r;
      try {
        r = validate_witness(*sys, w);
      } catch (const std::exception& e) {
        ADD_FAILURE() << "synthetic witness " << i << ": validate_witness threw " << e.what();
        continue;
      }
      EXPECT_TRUE(one_line(r.reason)) << r.reason;
      if (absurd_mode) {
        EXPECT_TRUE(r.malformed && !r.valid) << "witness " << i << ": " << r.reason;
      }
      // Through the file format too: what hyfal writes, it parses back to the same verdict, or
      // the parser rejects it first (a transition below -1 is out of its range).
      bool parser_rejects = false;
      for (const auto& p : t.pieces) parser_rejects = parser_rejects || p.transition < -1;
      if (parser_rejects) {
        EXPECT_TRUE(r.malformed) << r.reason;
      }
      try {
        const Witness back = witness_from_text(to_json(w).dump());
        EXPECT_FALSE(parser_rejects);
        EXPECT_EQ(validate_witness(*sys, back).reason, r.reason);
      } catch (const WitnessError& e) {
        EXPECT_TRUE(parser_rejects) << e.what();
      }
      if (HasFailure()) return;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// (b) Settings

const std::vector<std::string> kSettingTexts = {
    "", " ", "0", "-0", "1", "-1", "2", "-5", "0.5", "1.5", "2.5", "1e-300", "1e300", "1e999", "-1e999", "nan",
    "NaN", "inf", "-inf", "Infinity", "2147483647", "2147483648", "-2147483648", "9223372036854775808",
    "18446744073709551616", "true", "false", "null", "[]", "[1,2]", "{}", "\"x\"", "x", "random", "student",
    "t2go", "uniform", "adaptive", "tree", "safer", "original", "esposito5", "deg", "rad", "\xff\xfe",
    "a\nb", "5 6", "  7  ", "0x10", "1_000", "1e", "--1"};

// A resolved instance small enough to build in a test: integer sizes no larger than 64 or their
// default. Larger ones (a 4096² maze, 10^5 input levels) are bounded by the declared parameter
// ranges, not by make; they would only make this test slow.
bool small_instance(const std::vector<OptionSpec>& specs, const Json& resolved) {
  for (const auto& s : specs)
    if (s.default_value.is_number_integer()) {
      const auto v = resolved.at(s.key).get<std::int64_t>();
      if (v > std::max<std::int64_t>(64, s.default_value.get<std::int64_t>())) return false;
    }
  return true;
}

bool same_kind(const Json& a, const Json& b) {
  if (a.is_number_integer()) return b.is_number_integer();
  if (a.is_number()) return b.is_number() && std::isfinite(b.get<double>());
  return a.type() == b.type();
}

std::string random_setting_text(Dice& d, const Json& like) {
  switch (d.below(4)) {
    case 0: {  // the default, mutated
      std::string t = like.is_string() ? like.get<std::string>() : like.dump();
      mutate_bytes(t, d);
      return t;
    }
    case 1: return std::to_string(static_cast<std::int64_t>(d.g() >> d.below(64)) * (d.chance(0.5) ? 1 : -1));
    default: return d.pick(kSettingTexts);
  }
}

struct SettingsStats {
  int inputs = 0, rejected = 0, resolved = 0, made = 0, make_rejected = 0;
};

// One random list of settings against specs; make (when given) builds from the result.
template <class Make>
void check_settings(const std::vector<OptionSpec>& specs, Dice& d, SettingsStats& st, const std::string& what,
                    bool make_small_only, Make make) {
  ++st.inputs;
  std::vector<std::pair<std::string, std::string>> sets;
  const std::size_t count = d.below(4);
  for (std::size_t k = 0; k < count; ++k) {
    const OptionSpec* spec = specs.empty() ? nullptr : &specs[d.below(specs.size())];
    std::string key = spec && d.chance(0.9) ? spec->key : d.pick(kSettingTexts);
    sets.emplace_back(key, random_setting_text(d, spec ? spec->default_value : Json(1)));
  }
  std::string context = what;
  for (const auto& [k, v] : sets) context += " " + k + "=" + v;
  Json resolved;
  try {
    resolved = resolve_options(specs, sets);
  } catch (const OptionError&) {
    ++st.rejected;
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << context << ": resolve_options threw a " << typeid(e).name() << ": " << e.what();
    return;
  }
  ++st.resolved;
  for (const auto& s : specs) {
    ASSERT_TRUE(resolved.contains(s.key)) << context;
    EXPECT_TRUE(same_kind(s.default_value, resolved.at(s.key)))
        << context << ": " << s.key << " = " << show(resolved.at(s.key)) << " has another type than its default";
  }
  if (make_small_only && !small_instance(specs, resolved)) return;
  try {
    make(resolved);
    ++st.made;
  } catch (const std::invalid_argument&) {  // OptionError included
    ++st.make_rejected;
    return;
  } catch (const std::exception& e) {
    ADD_FAILURE() << context << ": make threw a " << typeid(e).name() << ": " << e.what();
    return;
  }
  // What was built is stored (instance key, method config): it must serialize.
  try {
    (void)resolved.dump();
  } catch (const Json::exception& e) {
    ADD_FAILURE() << context << ": the accepted settings cannot be stored: " << e.what();
  }
}

TEST(FuzzSettings, SuiteParametersAndMethodOptions) {
  Dice d(fuzz_seed() ^ 0x5e77ULL);
  SettingsStats st;
  const int n = budget(5000);
  for (int i = 0; i < n && !HasFailure(); ++i) {
    if (d.chance(0.5)) {
      const SuiteEntry& suite = d.pick(all_suites());
      check_settings(suite.parameters, d, st, "suite " + suite.name, true,
                     [&](const Json& r) { (void)suite.make(r); });
    } else {
      const MethodEntry& method = d.pick(all_methods());
      check_settings(method.options, d, st, "method " + method.name, false,
                     [&](const Json& r) { (void)method.make(r); });
    }
  }
  EXPECT_GT(st.rejected, 0);
  EXPECT_GT(st.made, 0);
  std::printf("[fuzz] %d settings lists: %d rejected, %d resolved, %d built, %d rejected by make\n", st.inputs,
              st.rejected, st.resolved, st.made, st.make_rejected);
}

// parse_option_value on its own: a value of the declared type, or an OptionError.
TEST(FuzzSettings, ParseOptionValueReturnsTheDeclaredTypeOrOptionError) {
  Dice d(fuzz_seed() ^ 0x7a1eULL);
  const std::vector<Json> likes = {Json(1), Json(1.0), Json(true), Json("s"), Json::array({1}), Json(-1.0)};
  const int n = budget(3000);
  int rejected = 0;
  for (int i = 0; i < n && !HasFailure(); ++i) {
    const Json& like = d.pick(likes);
    const std::string text = random_setting_text(d, like);
    try {
      const Json v = parse_option_value("key", text, like);
      EXPECT_TRUE(same_kind(like, v)) << "'" << text << "' as " << like.dump() << " gave " << show(v);
    } catch (const OptionError&) {
      ++rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "'" << text << "': parse_option_value threw a " << typeid(e).name() << ": " << e.what();
    }
  }
  EXPECT_GT(rejected, 0);
}

// --- (c) table and experiment files --------------------------------------------------------------

#ifndef HYFAL_SOURCE_DIR
#error "HYFAL_SOURCE_DIR (the source tree, for experiments/) must be defined"
#endif

// TOML values and fragments: every type, ranges' edges, the paper's marks, broken syntax.
const std::vector<std::string> kTomlTexts = {
    "0", "-1", "1e999", "nan", "inf", "-inf", "9223372036854775807", "9223372036854775808", "1_000", "0x10",
    "\"\"", "\"N/A\"", "\"X\"", "\"x\\ny\"", "'a'", "true", "[]", "[[]]", "[1, \"a\"]", "{}", "{ a = 1 }",
    "1979-05-27", "[rows]", "[[rows]]", "[profile.smoke]", "[sweep]", "=", "\"", "[", "]", "{", "\n", "#", "a.b.c = 1"};

// One edit of a TOML text: a byte-level mutation, or a line deleted, duplicated or replaced, or a
// value or key replaced by one of kTomlTexts.
void mutate_toml(std::string& t, Dice& d) {
  std::vector<std::string> lines;
  std::string line;
  for (const char c : t) {
    if (c == '\n') {
      lines.push_back(line);
      line.clear();
    } else {
      line += c;
    }
  }
  lines.push_back(line);
  const std::size_t i = d.below(lines.size());
  switch (d.below(6)) {
    case 0: mutate_bytes(t, d); return;
    case 1: lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(i)); break;
    case 2: lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), lines[d.below(lines.size())]); break;
    case 3: {  // a value replaced
      const auto eq = lines[i].find(" = ");
      if (eq != std::string::npos) lines[i] = lines[i].substr(0, eq + 3) + d.pick(kTomlTexts);
      break;
    }
    case 4: {  // a key renamed
      const auto eq = lines[i].find(" = ");
      if (eq != std::string::npos) lines[i] = d.pick(kTomlTexts) + lines[i].substr(eq);
      break;
    }
    default: lines[i] = d.pick(kTomlTexts); break;
  }
  t.clear();
  for (std::size_t k = 0; k < lines.size(); ++k) t += (k ? "\n" : "") + lines[k];
}

TEST(FuzzTomlFiles, MutatedTableAndExperimentFilesOnlyThrowExperimentFileErrorInOneLine) {
  std::vector<std::pair<std::string, bool>> seeds;  // text, is a paper table
  for (const EmbeddedFile& f : embedded_paper_table_files()) seeds.emplace_back(std::string(f.text), true);
  {
    std::ifstream in(fs::path(HYFAL_SOURCE_DIR) / "experiments" / "example.toml", std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    seeds.emplace_back(ss.str(), false);
  }
  ASSERT_GE(seeds.size(), 9u);
  Dice d(fuzz_seed() ^ 0x70d1ULL);
  const int n = budget(3000);
  int rejected = 0, accepted = 0;
  for (int i = 0; i < n && !HasFailure(); ++i) {
    const auto& [seed, is_table] = d.pick(seeds);
    std::string text = seed;
    for (std::size_t k = 0, rounds = 1 + d.below(3); k < rounds; ++k) mutate_toml(text, d);
    try {
      if (is_table)
        (void)load_paper_table(text, "fuzz.toml");
      else
        (void)load_experiment_file(text, "fuzz.toml");
      ++accepted;
    } catch (const ExperimentFileError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
      EXPECT_EQ(m.rfind("fuzz.toml", 0), 0u) << m;
      ++rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "threw a " << typeid(e).name() << ": " << e.what() << "\n--- input:\n" << text;
    }
  }
  EXPECT_GT(rejected, 0);
  EXPECT_GT(accepted, 0);
  std::printf("[fuzz] %d table/experiment files: %d rejected, %d accepted\n", n, rejected, accepted);
}

}  // namespace
}  // namespace hyfal
