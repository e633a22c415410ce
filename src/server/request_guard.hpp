// Who may talk to the viewer: the checks every HTTP request and WebSocket upgrade passes before
// its token is looked at, the token's places (the address, then a cookie), and the page's
// Content-Security-Policy. Pure functions of the request's headers, tested on their own.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace imx::server {

struct RequestGuard {
  // --allow-origin: origins ("http://viewer.example:8080") a page may come from besides the
  // viewer's own address; their hosts are allowed as Host too.
  std::vector<std::string> allowed_origins;

  // Empty when a request sent with this Host header may be answered, else why not. A Host must
  // be an IP address, "localhost" or an allowed origin's host: a DNS name pointing at this
  // machine (DNS rebinding) is refused, so a page from elsewhere cannot read the viewer.
  std::string check_host(std::string_view host) const;
  // Empty when a request with this Origin header (empty: none, as for a typed address) may be
  // answered: the page's own origin (http://HOST, HOST as the Host header says), or an allowed
  // one. Anything else (another site, another port, "null") is refused, with why.
  std::string check_origin(std::string_view origin, std::string_view host) const;
};

// The cookie that carries a session's token, named by the port so that viewers on one machine
// do not overwrite each other's: "imx_token_8080".
std::string token_cookie_name(uint16_t port);
// The token a request carries: its address's ?token= (when not empty), else its cookie of
// `cookie_name` in the Cookie header; empty when neither.
std::string_view request_token(std::string_view target, std::string_view cookie_header,
                               std::string_view cookie_name);

// The Content-Security-Policy of the viewer's responses: only the page's own scripts (and
// inline ones carrying `nonce`), styles and connections to its own host, images from blobs,
// no frames, forms or plugins.
std::string content_security_policy(std::string_view host, std::string_view nonce);

}  // namespace imx::server
