// The JSON replies of the server's routes (server.cpp, web_routes.cpp): a document, or the API's
// one-line error {"error": "..."} (docs/SERVICE.md, "The API").
#pragma once

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <string>

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

}  // namespace brdfbake::server
