// JSON from untrusted sources (jobs, scenes, material files, sidecars, server requests): parsed with a
// depth and size limit, every error naming the field's path, and quoted in messages by a short
// excerpt only (docs/RELIABILITY.md, "Untrusted input").
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace brdfbake::io {

inline constexpr int kJsonMaxDepth = 64;
inline constexpr std::size_t kJsonMaxBytes = std::size_t(64) << 20;

// Parses `text`, never recursing (nlohmann's SAX parser, a DOM built on an explicit stack). Throws
// brdfbake::Error:
//   "<origin>: JSON nested deeper than 64 levels (at <path>)"
//   "<origin>: larger than 64 MiB (<n> bytes)"
//   "<origin>: <path>: the number <token> is out of range (not a finite double)"   e.g. 1e999
//   "<origin>: malformed JSON: <the library's words, shortened> (at <path>)"
// where <path> is the field as a job spells it: "tables[0].size".
nlohmann::ordered_json parse_json(const std::string& text, const std::string& origin);

// A value as messages quote it: numbers, booleans and null in full, strings up to 40 characters,
// arrays and objects by their size ("an array of 3", "an object of 2 fields"); never recursive.
std::string json_excerpt(const nlohmann::ordered_json& value);

// Reads a whole file for parse_json, refusing folders, missing and unreadable files and files over
// the limit with a one-line message naming `what` and the path (Error); a read that fails part-way
// is an IoError.
std::string read_text_file(const std::string& path, const std::string& what);

// The text of a document brdfbake writes (manifests, sidecars, SH coefficients): never throws on
// strings that are not UTF-8 (a path or a name from the command line), whose bad bytes become U+FFFD.
std::string json_text(const nlohmann::ordered_json& document, int indent = 2);

}  // namespace brdfbake::io
