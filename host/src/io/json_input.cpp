#include "io/json_input.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "brdfbake/error.hpp"
#include "io/special_files.hpp"

namespace brdfbake::io {

namespace {

using json = nlohmann::ordered_json;

std::string shorten(const std::string& s, std::size_t n = 160) { return s.size() <= n ? s : s.substr(0, n) + "..."; }

// A DOM built from SAX events on an explicit stack (nlohmann's own DOM parser, with the two things it
// lacks: a depth limit, and the path of the value being read when an error occurs).
class Builder {
 public:
  enum class Stop { None, Depth, Overflow, Syntax };

  json root;
  Stop stop = Stop::None;
  std::string token;   // the number's text, for Overflow
  std::string detail;  // the library's message, for Syntax

  // "tables[0].size": where the next value goes (or the innermost container, at a depth error).
  std::string path() const {
    std::string p;
    for (size_t k = 0; k < stack_.size(); ++k) {
      const Frame& f = stack_[k];
      if (f.node->is_array()) {
        // an open child is the array's last element; at the top, the next value's index
        const size_t n = f.node->size();
        p += "[" + std::to_string(k + 1 < stack_.size() && n > 0 ? n - 1 : n) + "]";
      } else if (f.has_key) {
        p += (p.empty() ? "" : ".") + shorten(f.key, 60);
      }
    }
    return p;
  }

  // SAX events (nlohmann::json_sax).
  bool null() { return value(nullptr); }
  bool boolean(bool v) { return value(v); }
  bool number_integer(json::number_integer_t v) { return value(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value(v); }
  bool number_float(json::number_float_t v, const json::string_t&) { return value(v); }
  bool string(json::string_t& v) { return value(std::move(v)); }
  bool binary(json::binary_t& v) { return value(std::move(v)); }
  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool key(json::string_t& k) {
    stack_.back().key = std::move(k);
    stack_.back().has_key = true;
    return true;
  }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool parse_error(std::size_t, const std::string& last_token, const json::exception& e) {
    // A number the lexer read but a double cannot hold (1e999) is out_of_range.406.
    if (e.id == 406) {
      stop = Stop::Overflow;
      token = shorten(last_token, 40);
    } else {
      stop = Stop::Syntax;
      // "[json.exception.parse_error.101] parse error at line 1, column 2: ..." -> from "parse error"
      detail = e.what();
      const auto bracket = detail.find("] ");
      if (detail.rfind("[json.exception.", 0) == 0 && bracket != std::string::npos) detail = detail.substr(bracket + 2);
      detail = shorten(detail);
    }
    return false;
  }

 private:
  struct Frame {
    json* node;
    std::string key;
    bool has_key = false;
  };
  std::vector<Frame> stack_;

  // Where a new value goes: the root, the end of the open array, or the open object's key.
  json* slot() {
    if (stack_.empty()) return &root;
    Frame& f = stack_.back();
    if (f.node->is_array()) {
      f.node->push_back(nullptr);
      return &f.node->back();
    }
    return &(*f.node)[f.key];  // a repeated key: the last value wins (as nlohmann's DOM parser)
  }
  template <class V>
  bool value(V&& v) {
    *slot() = json(std::forward<V>(v));
    return true;
  }
  bool open(json empty) {
    if (static_cast<int>(stack_.size()) >= kJsonMaxDepth) {
      stop = Stop::Depth;
      return false;
    }
    json* s = slot();
    *s = std::move(empty);
    stack_.push_back({s, {}, false});
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }
};

}  // namespace

nlohmann::ordered_json parse_json(const std::string& text, const std::string& origin) {
  if (text.size() > kJsonMaxBytes)
    throw Error(origin + ": larger than " + std::to_string(kJsonMaxBytes >> 20) + " MiB (" +
                std::to_string(text.size()) + " bytes)");
  Builder b;
  bool ok = false;
  try {
    ok = json::sax_parse(text, &b);
  } catch (const json::exception& e) {  // not expected: the SAX interface reports through parse_error
    throw Error(origin + ": malformed JSON: " + shorten(e.what()));
  }
  if (ok) return std::move(b.root);
  const std::string at = shorten(b.path(), 80);
  switch (b.stop) {
    case Builder::Stop::Depth:
      throw Error(origin + ": JSON nested deeper than " + std::to_string(kJsonMaxDepth) + " levels" +
                  (at.empty() ? "" : " (at " + at + ")"));
    case Builder::Stop::Overflow:
      throw Error(origin + ": " + (at.empty() ? std::string("the document") : at) + ": the number " + b.token +
                  " is out of range (not a finite double)");
    default:
      throw Error(origin + ": malformed JSON: " + (b.detail.empty() ? std::string("parse error") : b.detail) +
                  (at.empty() ? "" : " (at " + at + ")"));
  }
}

std::string json_excerpt(const nlohmann::ordered_json& v) {
  if (v.is_array()) return v.empty() ? "an empty array" : "an array of " + std::to_string(v.size());
  if (v.is_object()) return v.empty() ? "an empty object" : "an object of " + std::to_string(v.size()) + " fields";
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    return json_text(nlohmann::ordered_json(shorten(s, 40)), -1);
  }
  return json_text(v, -1);  // a number, a boolean or null: flat
}

std::string json_text(const nlohmann::ordered_json& document, int indent) {
  return document.dump(indent, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string read_text_file(const std::string& path, const std::string& what) {
  // A FIFO or a character device (a pipe, /dev/stdin) is read as a stream: at most one byte more
  // than the limit, cancellable while it waits for data (io/special_files.hpp).
  return read_input(path, what, kJsonMaxBytes, std::to_string(kJsonMaxBytes >> 20) + " MiB", Streams::Yes);
}

}  // namespace brdfbake::io
