// How trials travel between the ranks of a distributed run: a job (what to run) from rank 0 to a
// worker, a result (record, series, witness text) back. CBOR (nlohmann's binary JSON): compact,
// and exact for every double, NaN and infinities included, so a record stored on rank 0 equals
// the one the worker computed, and a witness's bytes are the worker's bytes.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "core/model/system.hpp"
#include "parallel/trial_engine.hpp"

namespace hyfal {

// Builds the system of a suite instance (canonical JSON text, as in TrialKey::instance). The app
// supplies it (it knows the suite registry; parallel/ does not). A worker caches what it returns.
using SystemResolver = std::function<std::shared_ptr<const System>(const std::string& suite, const std::string& instance)>;

std::string encode_job(const TrialJob& job);
// Throws std::invalid_argument for bytes that are not a job, or a method this build lacks.
TrialJob decode_job(const std::string& bytes, const SystemResolver& resolve);

std::string encode_result(const TrialResult& result);
// Throws std::invalid_argument for bytes that are not a result.
TrialResult decode_result(const std::string& bytes);

}  // namespace hyfal
