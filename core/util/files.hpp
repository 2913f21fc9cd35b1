// Files written whole: the one way hyfal writes a witness, a tree or a table.
#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/util/error.hpp"

namespace hyfal {

// Writes text to path through path.tmp and a rename, creating the parent folders: path holds
// either what it held before or all of text, never a part. Throws EnvironmentError, one line
// "cannot write <what> '<path>': <step>: <cause>" (what, e.g. "witness", may be empty), and leaves
// no temporary file. Callers check the folder up front (a bad path is bad input, exit 2); what
// fails here is the environment: a full disk, an I/O error, a permission lost since the check.
void write_file_atomic(const std::filesystem::path& path, const std::string& text, std::string_view what = {});

}  // namespace hyfal
