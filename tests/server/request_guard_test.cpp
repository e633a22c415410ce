// The viewer's request checks alone: hosts, origins, where a token is found, the policy.
#include "server/request_guard.hpp"

#include <gtest/gtest.h>

namespace imx::server {
namespace {

TEST(RequestGuard, HostsAreAddressesLocalhostOrAllowedNames) {
  RequestGuard g;
  for (const char* ok : {"127.0.0.1", "127.0.0.1:8080", "localhost:8080", "LOCALHOST", "[::1]:80",
                         "[::1]", "10.1.2.3:9000"})
    EXPECT_EQ(g.check_host(ok), "") << ok;
  for (const char* bad : {"", "evil.example", "evil.example:8080", "127.0.0.1.nip.io:8080",
                          "localhost:8080; script-src *", "localhost:x", "[::1", "[::1]x"})
    EXPECT_NE(g.check_host(bad), "") << bad;
  g.allowed_origins = {"http://viewer.example:8080"};
  EXPECT_EQ(g.check_host("viewer.example:8080"), "");
  EXPECT_NE(g.check_host("other.example:8080"), "");
}

TEST(RequestGuard, OriginsAreThePagesOwnOrAllowed) {
  RequestGuard g;
  EXPECT_EQ(g.check_origin("", "127.0.0.1:8080"), "");  // a typed address sends none
  EXPECT_EQ(g.check_origin("http://127.0.0.1:8080", "127.0.0.1:8080"), "");
  EXPECT_EQ(g.check_origin("http://LocalHost:9000", "localhost:9000"), "");  // an SSH tunnel
  EXPECT_NE(g.check_origin("http://evil.example", "127.0.0.1:8080"), "");
  EXPECT_NE(g.check_origin("http://127.0.0.1:8081", "127.0.0.1:8080"), "");
  EXPECT_NE(g.check_origin("null", "127.0.0.1:8080"), "");
  const std::string why = g.check_origin("http://evil.example\n", "127.0.0.1:8080");
  EXPECT_NE(why.find("'http://evil.example\\x0a'"), std::string::npos) << why;
  g.allowed_origins = {"https://viewer.example"};
  EXPECT_EQ(g.check_origin("https://viewer.example", "127.0.0.1:8080"), "");
}

TEST(RequestGuard, TheTokenComesFromTheAddressElseItsCookie) {
  const std::string name = token_cookie_name(8080);
  EXPECT_EQ(name, "imx_token_8080");
  EXPECT_EQ(request_token("/?token=abc", "", name), "abc");
  EXPECT_EQ(request_token("/js/main.js?x=1&token=abc", "imx_token_8080=def", name), "abc");
  EXPECT_EQ(request_token("/js/main.js", "a=1; imx_token_8080=def; b=2", name), "def");
  EXPECT_EQ(request_token("/js/main.js", "imx_token_8081=def", name), "");
  EXPECT_EQ(request_token("/js/main.js?tokens=abc", "", name), "");
  EXPECT_EQ(request_token("/js/main.js?token=", "imx_token_8080=def", name), "def");
  EXPECT_EQ(request_token("/", "", name), "");
}

TEST(RequestGuard, ThePolicyAllowsOnlyThePagesOwn) {
  const std::string p = content_security_policy("127.0.0.1:8080", "n0nce");
  EXPECT_NE(p.find("default-src 'none'"), std::string::npos);
  EXPECT_NE(p.find("script-src 'self' 'nonce-n0nce'"), std::string::npos);
  EXPECT_NE(p.find("connect-src 'self' ws://127.0.0.1:8080"), std::string::npos);
  EXPECT_NE(p.find("frame-ancestors 'none'"), std::string::npos);
  EXPECT_EQ(p.find("unsafe"), std::string::npos);
}

}  // namespace
}  // namespace imx::server
