#include "server/site_policy.hpp"

#include <algorithm>
#include <cctype>

#include "server/server.hpp"

namespace brdfbake::server {
namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool listed(const std::vector<std::string>& list, const std::string& value) {
  return std::any_of(list.begin(), list.end(), [&](const std::string& e) { return e == "*" || lower(e) == value; });
}

// Printable for a one-line message (the header is the client's: no control bytes, at most 100 bytes).
std::string shown(const std::string& s) {
  std::string out;
  for (char c : s.substr(0, 100)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
  return s.size() > 100 ? out + "..." : out;
}

}  // namespace

std::string host_name_of(const std::string& host_header) {
  const std::string h = lower(host_header);
  if (h.empty()) return "";
  if (h.front() == '[') {  // an IPv6 literal, with or without a port
    const auto close = h.find(']');
    if (close == std::string::npos) return "";
    const std::string rest = h.substr(close + 1);
    if (!rest.empty() && (rest[0] != ':' || rest.find_first_not_of("0123456789", 1) != std::string::npos)) return "";
    return h.substr(1, close - 1);
  }
  const auto colon = h.find(':');
  const std::string name = h.substr(0, colon);
  if (colon != std::string::npos && h.find_first_not_of("0123456789", colon + 1) != std::string::npos) return "";
  if (name.empty() || name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789.-_") != std::string::npos) return "";
  return name;
}

std::string refuse_by_site(const SitePolicy& policy, const std::string& method, const std::string& host_header,
                           const std::string& origin, const std::string& sec_fetch_site) {
  const std::string name = host_name_of(host_header);
  const bool host_ok =
      !policy.check_host || host_header.empty() ||
      (!name.empty() && (is_loopback(name) || name == lower(policy.listen_host) || listed(policy.allowed_hosts, name)));
  if (!host_ok)
    return "Host '" + shown(host_header) +
           "' is not a name of this server (a page that made a name of its own point here cannot read it; "
           "allow a name with --allowed-hosts)";
  if (method == "GET" || method == "HEAD" || method == "OPTIONS") return "";
  if (origin.empty()) {
    const std::string site = lower(sec_fetch_site);
    if (site == "cross-site" || site == "same-site")
      return "a " + site + " request from a browser without an Origin header is refused";
    return "";
  }
  const std::string o = lower(origin);
  if (o != "null" && listed(policy.allowed_origins, o)) return "";
  if (o != "null" && !host_header.empty() && o == "http://" + lower(host_header)) return "";
  return "a request from the page of another origin ('" + shown(origin) +
         "') may not change anything here (allow an origin with --allowed-origins)";
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t comma = text.find(',', start);
    if (comma == std::string::npos) comma = text.size();
    std::string e = text.substr(start, comma - start);
    const auto b = e.find_first_not_of(" \t"), en = e.find_last_not_of(" \t");
    if (b != std::string::npos) out.push_back(e.substr(b, en - b + 1));
    start = comma + 1;
  }
  return out;
}

}  // namespace brdfbake::server
