#include "server/request_guard.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>
#include <boost/asio/ip/address.hpp>

namespace imx::server {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// "host", "host:port", "[v6]", "[v6]:port" -> the host alone, lower case, without brackets.
std::string host_name(std::string_view host) {
  if (!host.empty() && host.front() == '[') {
    const size_t close = host.find(']');
    return lower(host.substr(1, close == std::string_view::npos ? host.npos : close - 1));
  }
  return lower(host.substr(0, host.find(':')));
}

// The host[:port] of an origin "scheme://host[:port]".
std::string_view origin_authority(std::string_view origin) {
  const size_t sep = origin.find("://");
  return sep == std::string_view::npos ? std::string_view{} : origin.substr(sep + 3);
}

bool is_ip_address(const std::string& host) {
  boost::system::error_code ec;
  boost::asio::ip::make_address(host, ec);
  return !ec;
}

// Control characters and overlong values are shown cut and escaped, never raw.
std::string shown(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 100)) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == '\'')
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    else
      out += c;
  }
  return s.size() > 100 ? out + "..." : out;
}

// Whatever follows the host: nothing, or ":" and a port number.
bool port_part_ok(std::string_view host) {
  size_t end = 0;
  if (!host.empty() && host.front() == '[') {
    end = host.find(']');
    if (end == std::string_view::npos) return false;
    ++end;
  } else {
    end = std::min(host.find(':'), host.size());
  }
  const std::string_view rest = host.substr(end);
  if (rest.empty()) return true;
  return rest.size() >= 2 && rest.size() <= 6 && rest.front() == ':' &&
         std::all_of(rest.begin() + 1, rest.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

std::string RequestGuard::check_host(std::string_view host) const {
  const std::string name = host_name(host);
  if (name.empty()) return "the request names no Host";
  if (!port_part_ok(host)) return fmt::format("Host '{}' is not a host and port", shown(host));
  if (name == "localhost" || is_ip_address(name)) return {};
  for (const std::string& origin : allowed_origins)
    if (host_name(origin_authority(origin)) == name) return {};
  return fmt::format(
      "Host '{}' is not this viewer's address: open it by IP address or localhost, or start "
      "serve with --allow-origin for a name",
      shown(host));
}

std::string RequestGuard::check_origin(std::string_view origin, std::string_view host) const {
  if (origin.empty()) return {};
  const std::string own = lower(origin);
  if (!host.empty() && (own == "http://" + lower(host) || own == "https://" + lower(host)))
    return {};
  for (const std::string& allowed : allowed_origins)
    if (own == lower(allowed)) return {};
  return fmt::format(
      "Origin '{}' is not this viewer's page (its own is http://{}); start serve with "
      "--allow-origin to allow another",
      shown(origin), shown(host));
}

std::string token_cookie_name(uint16_t port) {
  return fmt::format("imx_token_{}", port);
}

std::string_view request_token(std::string_view target, std::string_view cookie_header,
                               std::string_view cookie_name) {
  // The address's ?token= (hex: no percent-decoding needed, an encoded one does not match).
  if (const size_t q = target.find('?'); q != std::string_view::npos) {
    std::string_view query = target.substr(q + 1);
    while (!query.empty()) {
      const size_t amp = query.find('&');
      const std::string_view pair = query.substr(0, amp);
      if (pair.substr(0, 6) == "token=" && pair.size() > 6) return pair.substr(6);
      if (amp == std::string_view::npos) break;
      query.remove_prefix(amp + 1);
    }
  }
  // "a=1; imx_token_8080=abc; b=2"
  while (!cookie_header.empty()) {
    const size_t semi = cookie_header.find(';');
    std::string_view pair = cookie_header.substr(0, semi);
    while (!pair.empty() && pair.front() == ' ') pair.remove_prefix(1);
    const size_t eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == cookie_name)
      return pair.substr(eq + 1);
    if (semi == std::string_view::npos) break;
    cookie_header.remove_prefix(semi + 1);
  }
  return {};
}

std::string content_security_policy(std::string_view host, std::string_view nonce) {
  return fmt::format(
      "default-src 'none'; script-src 'self' 'nonce-{}'; style-src 'self'; img-src 'self' blob: "
      "data:; connect-src 'self' ws://{} wss://{}; base-uri 'none'; form-action 'none'; "
      "frame-ancestors 'none'",
      nonce, host, host);
}

}  // namespace imx::server
