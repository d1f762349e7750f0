// The bridge's gzip of large answers (web/bridge/gzip.*): Accept-Encoding
// read as RFC 9110 says, and a body that inflates back to itself.
#include <gtest/gtest.h>

#include <string>

#include <zlib.h>

#include "bridge/gzip.hpp"

namespace groundsim::web {
namespace {

std::string gunzip(const std::string& z) {
  z_stream s{};
  EXPECT_EQ(inflateInit2(&s, 15 + 16), Z_OK);  // gzip wrapper only
  std::string out(1 << 22, '\0');
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(z.data()));
  s.avail_in = static_cast<uInt>(z.size());
  s.next_out = reinterpret_cast<Bytef*>(out.data());
  s.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(inflate(&s, Z_FINISH), Z_STREAM_END);
  out.resize(out.size() - s.avail_out);
  inflateEnd(&s);
  return out;
}

TEST(Gzip, AcceptEncodingIsReadWithItsWeights) {
  EXPECT_TRUE(acceptsGzip("gzip"));
  EXPECT_TRUE(acceptsGzip("gzip, deflate, br, zstd"));  // Chromium's
  EXPECT_TRUE(acceptsGzip("br;q=1.0, gzip;q=0.5"));
  EXPECT_TRUE(acceptsGzip("*"));
  EXPECT_FALSE(acceptsGzip(""));
  EXPECT_FALSE(acceptsGzip("identity"));
  EXPECT_FALSE(acceptsGzip("gzip;q=0"));
  EXPECT_FALSE(acceptsGzip("x-gzip2, br"));
}

TEST(Gzip, ABodyInflatesBackToItself) {
  std::string body;
  for (int k = 0; k < 20000; ++k) body += "{\"seq\":" + std::to_string(k) + ",\"position\":[1.25,-3.5,0.55]},";
  const auto z = gzip(body);
  ASSERT_TRUE(z);
  EXPECT_EQ(static_cast<unsigned char>((*z)[0]), 0x1f);  // the gzip magic
  EXPECT_EQ(static_cast<unsigned char>((*z)[1]), 0x8b);
  EXPECT_LT(z->size(), body.size() / 4);
  EXPECT_EQ(gunzip(*z), body);
  EXPECT_EQ(gunzip(*gzip("")), "");
}

}  // namespace
}  // namespace groundsim::web
