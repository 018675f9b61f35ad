// The replies of the server's routes (server.cpp, web_routes.cpp): a JSON document, or the API's
// one-line error {"error": "..."} (docs/SERVICE.md, "The API"); the one Content-Disposition of a download.
#pragma once

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace brdfbake::server {

inline void reply_json(httplib::Response& res, int status, const nlohmann::ordered_json& body) {
  res.status = status;
  res.set_content(body.dump(2) + "\n", "application/json");
}

inline void reply_error(httplib::Response& res, int status, const std::string& message) {
  nlohmann::ordered_json o;
  o["error"] = message;
  reply_json(res, status, o);
}

// The Content-Disposition of a download named `name` (RFC 6266): `attachment; filename="ASCII";
// filename*=UTF-8''PERCENT-ENCODED`. The quoted form keeps printable ASCII but the quote, the
// backslash and ';' (each '_'), so no name can end the quoted string and add a parameter (a name like
// `a"; filename*=UTF-8''evil.exe`); the extended form percent-encodes every byte outside RFC 5987's
// attr-char, so it carries any name exactly. Both are cut at 200 bytes of the name.
inline std::string content_disposition(const std::string& name) {
  const std::string n = name.substr(0, 200);
  std::string quoted, extended;
  static const char* const kHex = "0123456789ABCDEF";
  for (char ch : n) {
    const auto c = static_cast<unsigned char>(ch);
    quoted += (c >= 0x20 && c < 0x7f && ch != '"' && ch != '\\' && ch != ';') ? ch : '_';
    const bool attr_char = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                           std::string_view("!#$&+-.^_`|~").find(ch) != std::string_view::npos;
    if (attr_char) {
      extended += ch;
    } else {
      extended += '%';
      extended += kHex[c >> 4];
      extended += kHex[c & 15];
    }
  }
  return "attachment; filename=\"" + quoted + "\"; filename*=UTF-8''" + extended;
}

}  // namespace brdfbake::server
