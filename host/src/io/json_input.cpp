#include "io/json_input.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "brdfbake/error.hpp"

namespace brdfbake::io {

namespace {

class DepthError : public std::exception {};

std::string shorten(const std::string& s, std::size_t n = 160) { return s.size() <= n ? s : s.substr(0, n) + "..."; }

}  // namespace

nlohmann::ordered_json parse_json(const std::string& text, const std::string& origin) {
  using json = nlohmann::ordered_json;
  if (text.size() > kJsonMaxBytes)
    throw Error(origin + ": larger than " + std::to_string(kJsonMaxBytes >> 20) + " MiB (" + std::to_string(text.size()) +
                " bytes)");
  const json::parser_callback_t limit = [](int depth, json::parse_event_t, json&) {
    if (depth > kJsonMaxDepth) throw DepthError();
    return true;
  };
  try {
    return json::parse(text, limit);
  } catch (const DepthError&) {
    throw Error(origin + ": JSON nested deeper than " + std::to_string(kJsonMaxDepth) + " levels");
  } catch (const json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 2: ..." -> from "parse error"
    std::string what = e.what();
    const auto bracket = what.find("] ");
    if (what.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) what = what.substr(bracket + 2);
    throw Error(origin + ": malformed JSON: " + shorten(what));
  }
}

std::string json_excerpt(const nlohmann::ordered_json& v) {
  if (v.is_array()) return v.empty() ? "an empty array" : "an array of " + std::to_string(v.size());
  if (v.is_object()) return v.empty() ? "an empty object" : "an object of " + std::to_string(v.size()) + " fields";
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    return "\"" + shorten(s, 40) + "\"";
  }
  return v.dump();  // a number, a boolean or null: flat
}

std::string read_text_file(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error("cannot read " + what + " '" + path + "': it is a folder");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw Error("cannot read " + what + " '" + path + "': " +
                (fs::exists(path, ec) ? std::string(std::strerror(err ? err : EACCES)) : "no such file"));
  }
  const auto size = fs::file_size(path, ec);
  if (!ec && size > kJsonMaxBytes)
    throw Error("cannot read " + what + " '" + path + "': larger than " + std::to_string(kJsonMaxBytes >> 20) + " MiB");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw Error("cannot read " + what + " '" + path + "': read error");
  return s.str();
}

}  // namespace brdfbake::io
