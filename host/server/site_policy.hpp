// Which requests a server answers by where they come from (issue 34, class 4): a page of another
// origin must not drive a server on loopback (a cross-origin POST needs no preflight when its
// Content-Type is a "simple" one), and a foreign Host name must not read it (DNS rebinding: a name the
// attacker controls made to resolve to 127.0.0.1, so the page is "same-origin" with the server).
// The rules are those of the local development servers of the field (webpack-dev-server's
// allowedHosts, Vite's server.allowedHosts, Jupyter's allow_origin): docs/SERVICE.md, "Who may call".
#pragma once

#include <string>
#include <vector>

namespace brdfbake::server {

struct SitePolicy {
  std::string listen_host;                   // --listen's host (always an allowed Host name)
  bool check_host = true;                    // false: any Host (a server with a token and no --allowed-hosts)
  std::vector<std::string> allowed_hosts;    // --allowed-hosts: more Host names; "*" = any
  std::vector<std::string> allowed_origins;  // --allowed-origins: more origins that may write; "*" = any
};

// The host name of a Host header ("127.0.0.1:8737" -> "127.0.0.1", "[::1]:8737" -> "::1"), lower case;
// "" when the header is malformed.
std::string host_name_of(const std::string& host_header);

// "" when the request may go on; otherwise the one-line reason for a 403.
//  - Host: a loopback name or address, the listen host, or one of allowed_hosts (when check_host);
//    a request without Host (HTTP/1.0 tools; no browser sends one) passes.
//  - Origin, for methods that change something (all but GET, HEAD, OPTIONS): absent (command-line
//    clients), this server's own origin ("http://" + the Host header, the page it serves), or one of
//    allowed_origins; "null" (sandboxed frames, file: pages) never. A browser request that says it is
//    cross-site (Sec-Fetch-Site) without an Origin is refused too.
std::string refuse_by_site(const SitePolicy& policy, const std::string& method, const std::string& host_header,
                           const std::string& origin, const std::string& sec_fetch_site);

// A comma-separated option's entries, trimmed, empty ones dropped.
std::vector<std::string> split_list(const std::string& text);

}  // namespace brdfbake::server
