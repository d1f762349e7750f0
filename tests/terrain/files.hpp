// Files for the terrain tests, written at test time: grayscale PNGs
// (libpng), CSVs, scenarios, in a fresh directory per test.
#pragma once

#include <png.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

namespace groundsim::test {

// A directory of its own for the running test, removed by the destructor.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = std::filesystem::temp_directory_path() /
           ("groundsim_terrain_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::filesystem::path operator/(const std::string& name) const { return path / name; }
};

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

// values row by row (row 0 first = the top of the image); depth 8 or 16;
// colour_type PNG_COLOR_TYPE_GRAY unless a test wants another.
inline void writePng(const std::filesystem::path& p, int w, int h, int depth, const std::vector<unsigned>& values,
                     int colour_type = PNG_COLOR_TYPE_GRAY) {
  std::filesystem::create_directories(p.parent_path());
  std::FILE* f = std::fopen(p.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + p.string());
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    throw std::runtime_error("libpng failed writing " + p.string());
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, depth, colour_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const int channels = colour_type == PNG_COLOR_TYPE_RGB ? 3 : 1;
  const int bytes = depth / 8;
  std::vector<unsigned char> row(static_cast<size_t>(w) * channels * bytes);
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i)
      for (int c = 0; c < channels; ++c) {
        const unsigned v = values.empty() ? 0u : values[static_cast<size_t>(j) * w + i];
        unsigned char* px = row.data() + (static_cast<size_t>(i) * channels + c) * bytes;
        if (bytes == 2) {  // PNG stores 16-bit samples big-endian
          px[0] = static_cast<unsigned char>(v >> 8);
          px[1] = static_cast<unsigned char>(v & 0xff);
        } else {
          px[0] = static_cast<unsigned char>(v);
        }
      }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

}  // namespace groundsim::test
