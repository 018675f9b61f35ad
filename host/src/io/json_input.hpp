// JSON from untrusted sources (jobs, scenes, material files, server requests): parsed with a depth
// and size limit, and quoted in messages by a short excerpt only (docs/RELIABILITY.md).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace brdfbake::io {

inline constexpr int kJsonMaxDepth = 64;
inline constexpr std::size_t kJsonMaxBytes = std::size_t(64) << 20;

// Parses `text`; throws brdfbake::Error "<origin>: malformed JSON: <what>" (the library's own words,
// shortened), "<origin>: JSON nested deeper than 64 levels" or "<origin>: larger than 64 MiB".
nlohmann::ordered_json parse_json(const std::string& text, const std::string& origin);

// A value as messages quote it: numbers, booleans and null in full, strings up to 40 characters,
// arrays and objects by their size ("an array of 3", "an object of 2 fields"); never recursive.
std::string json_excerpt(const nlohmann::ordered_json& value);

// Reads a whole file for parse_json, refusing folders, unreadable files and files over the limit
// with a one-line message naming `what` and the path.
std::string read_text_file(const std::string& path, const std::string& what);

}  // namespace brdfbake::io
