#include "scenario/terrain_loader.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <csetjmp>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include <png.h>

namespace groundsim::scenario {
namespace fs = std::filesystem;
namespace {

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string countText(std::size_t n) {
  std::ostringstream s;
  s << n;
  return s.str();
}

void checkBudget(std::size_t nx, std::size_t ny, std::size_t max_samples) {
  // the limit first: a 1 x 10^9 header is too large before it is too thin
  if (ny > 0 && nx > max_samples / ny)
    throw TerrainError("is " + countText(nx) + " x " + countText(ny) + " = " + countText(nx * ny) +
                       " samples, more than the limit of " + countText(max_samples) + " (4097 x 4097)");
  if (nx < 2 || ny < 2)
    throw TerrainError("is " + countText(nx) + " x " + countText(ny) + " samples; a grid needs at least 2 x 2");
}

// True when `inner` is `outer` or lies below it (both canonical).
bool within(const fs::path& outer, const fs::path& inner) {
  auto o = outer.begin(), i = inner.begin();
  for (; o != outer.end(); ++o, ++i)
    if (i == inner.end() || *o != *i) return false;
  return true;
}

}  // namespace

fs::path resolveTerrainPath(const FileAccess& access, const std::string& name) {
  if (name.empty()) throw TerrainError("must not be empty");
  const fs::path p(name);
  fs::path full;
  std::error_code ec;
  switch (access.mode) {
    case FileAccess::Mode::None:
    case FileAccess::Mode::Collect:
      throw TerrainError("no file can be read here: this scenario came without its files (clients send them "
                         "with it; in process, name the scenario by its path or give the folder of its files)");
    case FileAccess::Mode::Assets:
      if (access.dir.empty())
        throw TerrainError(quoted(name) + " was not sent with the scenario (it is not in /assets; clients send "
                           "the files a scenario names with it: docs/protocol.md, Assets)");
      return resolveTerrainPath(FileAccess::confined(access.dir), name);
    case FileAccess::Mode::Local:
      full = p.is_absolute() ? p : fs::path(access.dir) / p;
      break;
    case FileAccess::Mode::Confined: {
      if (p.is_absolute() || p.has_root_name() || p.has_root_directory())
        throw TerrainError("absolute paths are refused: name a file inside the terrain directory");
      for (const fs::path& part : p)
        if (part == "..") throw TerrainError("\"..\" is refused: the file must be inside the terrain directory");
      const fs::path root = fs::canonical(access.dir, ec);
      if (ec) throw TerrainError("the terrain directory " + quoted(access.dir) + " does not exist");
      full = root / p;
      if (!fs::exists(full, ec)) throw TerrainError(quoted(name) + ": no such file in the terrain directory");
      // a symbolic link inside may still point anywhere: compare real paths
      const fs::path real = fs::canonical(full, ec);
      if (ec || !within(root, real))
        throw TerrainError(quoted(name) + " leads out of the terrain directory (through a symbolic link)");
      full = real;
      break;
    }
  }
  if (!fs::exists(full, ec)) throw TerrainError(quoted(full.string()) + ": no such file");
  if (!fs::is_regular_file(full, ec)) throw TerrainError(quoted(full.string()) + ": not a regular file");
  return full;
}

GridType gridTypeOf(const std::string& name) {
  std::string ext = fs::path(name).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".png") return GridType::Png;
  if (ext == ".csv" || ext == ".txt") return GridType::Csv;
  return GridType::Unknown;
}

Grid readGridBytes(const std::string& name, const std::string& bytes, std::size_t max_samples) {
  switch (gridTypeOf(name)) {
    case GridType::Png: return readPngBytes(name, bytes, max_samples);
    case GridType::Csv: return readCsvBytes(name, bytes, max_samples);
    case GridType::Unknown: break;
  }
  throw TerrainError(quoted(fs::path(name).filename().string()) + ": unknown file type (expected .png or .csv)");
}

Grid readGridFile(const fs::path& path, std::size_t max_samples) {
  switch (gridTypeOf(path.string())) {
    case GridType::Png: return readPng(path, max_samples);
    case GridType::Csv: return readCsv(path, max_samples);
    case GridType::Unknown: break;
  }
  throw TerrainError(quoted(path.filename().string()) + ": unknown file type (expected .png or .csv)");
}

Grid loadGrid(const FileAccess& access, const std::string& name, std::size_t max_samples) {
  if (access.mode == FileAccess::Mode::Assets && access.assets) {
    const auto it = access.assets->find(name);
    if (it != access.assets->end() && it->second) return readGridBytes(name, *it->second, max_samples);
  }
  return readGridFile(resolveTerrainPath(access, name), max_samples);
}

std::string loadFileBytes(const FileAccess& access, const std::string& name, std::size_t max_bytes) {
  if (access.mode == FileAccess::Mode::Assets && access.assets) {
    const auto it = access.assets->find(name);
    if (it != access.assets->end() && it->second) {
      if (it->second->size() > max_bytes)
        throw TerrainError(quoted(name) + ": " + countText(it->second->size()) + " bytes, more than the limit of " +
                           countText(max_bytes));
      return *it->second;
    }
  }
  return readFileBytes(resolveTerrainPath(access, name), max_bytes);
}

std::string readFileBytes(const fs::path& path, std::size_t max_bytes) {
  const std::string who = quoted(path.filename().string());
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) throw TerrainError(who + ": cannot read its size");
  // refused before reading: a huge file is not read into memory to be refused
  if (size > max_bytes)
    throw TerrainError(who + ": " + countText(size) + " bytes, more than the limit of " + countText(max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TerrainError(who + ": cannot open for reading");
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in.gcount()) != size) throw TerrainError(who + ": read error");
  return bytes;
}

// --- PNG (libpng) ---

namespace {

struct PngRead {
  const unsigned char* data = nullptr;  // the whole file, signature included
  std::size_t size = 0, at = 0;         // read position
  std::size_t max_samples = 0;
  Grid* out = nullptr;
  std::vector<unsigned char>* row = nullptr;
  char error[256] = {};   // libpng's message, or ours
  bool refused = false;   // ours (size, colour type): not libpng's
};

void pngError(png_structp png, png_const_charp msg) {
  auto* r = static_cast<PngRead*>(png_get_error_ptr(png));
  std::snprintf(r->error, sizeof r->error, "%s", msg);
  png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}

// libpng's input from memory: a read past the end is a truncated file.
void pngReadBytes(png_structp png, png_bytep out, png_size_t n) {
  auto* r = static_cast<PngRead*>(png_get_io_ptr(png));
  if (n > r->size - r->at) png_error(png, "truncated (the file ends inside its data)");
  std::memcpy(out, r->data + r->at, n);
  r->at += n;
}

// The libpng part: only plain data (and data reached through `r`) lives
// across setjmp, so the longjmp of an error skips no destructor.
bool decodePng(PngRead* r) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, r, pngError, pngWarning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    return false;
  }
  png_set_read_fn(png, r, pngReadBytes);
  r->at = 8;
  png_set_sig_bytes(png, 8);  // the caller checked the signature
  png_read_info(png, info);
  png_uint_32 w = 0, h = 0;
  int depth = 0, colour = 0, interlace = 0;
  png_get_IHDR(png, info, &w, &h, &depth, &colour, &interlace, nullptr, nullptr);
  auto refuse = [&](const std::string& why) {
    std::snprintf(r->error, sizeof r->error, "%s", why.c_str());
    r->refused = true;
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  };
  if (colour != PNG_COLOR_TYPE_GRAY)
    return refuse(colour == PNG_COLOR_TYPE_GRAY_ALPHA ? "has an alpha channel; heights must be plain grayscale"
                                                      : "is a colour image; heights must be grayscale (8 or 16 bit)");
  if (depth != 8 && depth != 16)
    return refuse("has " + std::to_string(depth) + "-bit samples; use 8 or 16 bits");
  if (interlace != PNG_INTERLACE_NONE) return refuse("is interlaced; save it without interlacing");
  // a decompression bomb is refused from its header, before any pixel
  try {
    checkBudget(w, h, r->max_samples);
  } catch (const TerrainError& e) {
    return refuse(e.what());
  }
  if (depth == 16 && std::endian::native == std::endian::little) png_set_swap(png);
  png_read_update_info(png, info);
  Grid& g = *r->out;
  g.nx = static_cast<int>(w);
  g.ny = static_cast<int>(h);
  g.bit_depth = depth;
  g.values.resize(static_cast<std::size_t>(w) * h);
  r->row->resize(png_get_rowbytes(png, info));
  const double scale = 1.0 / (depth == 16 ? 65535.0 : 255.0);
  for (png_uint_32 j = 0; j < h; ++j) {
    png_read_row(png, r->row->data(), nullptr);
    float* dst = g.values.data() + static_cast<std::size_t>(j) * w;
    if (depth == 16) {
      const auto* src = reinterpret_cast<const std::uint16_t*>(r->row->data());
      for (png_uint_32 i = 0; i < w; ++i) dst[i] = static_cast<float>(src[i] * scale);
    } else {
      const unsigned char* src = r->row->data();
      for (png_uint_32 i = 0; i < w; ++i) dst[i] = static_cast<float>(src[i] * scale);
    }
  }
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

}  // namespace

Grid readPngBytes(const std::string& name, const std::string& bytes, std::size_t max_samples) {
  const std::string who = quoted(fs::path(name).filename().string());
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8 || png_sig_cmp(data, 0, 8) != 0) throw TerrainError(who + ": not a PNG file");
  // the size from the IHDR chunk (always first: width and height at bytes
  // 16 and 20, big-endian), refused before libpng reads further
  if (bytes.size() >= 24 && std::memcmp(data + 12, "IHDR", 4) == 0) {
    auto be32 = [&](std::size_t at) {
      return (std::size_t{data[at]} << 24) | (std::size_t{data[at + 1]} << 16) | (std::size_t{data[at + 2]} << 8) |
             std::size_t{data[at + 3]};
    };
    try {
      checkBudget(be32(16), be32(20), max_samples);
    } catch (const TerrainError& e) {
      throw TerrainError(who + ": " + e.what());
    }
  }
  Grid g;
  std::vector<unsigned char> row;
  PngRead r;
  r.data = data;
  r.size = bytes.size();
  r.max_samples = max_samples;
  r.out = &g;
  r.row = &row;
  if (!decodePng(&r)) {
    std::string why = r.error[0] ? r.error : "cannot be decoded";
    throw TerrainError(who + (r.refused ? ": " : ": bad PNG: ") + why);
  }
  return g;
}

Grid readPng(const fs::path& path, std::size_t max_samples) {
  return readPngBytes(path.filename().string(), readFileBytes(path, kMaxGridFileBytes), max_samples);
}

// --- CSV ---

Grid readCsv(const fs::path& path, std::size_t max_samples) {
  // generous: 40 characters per sample
  return readCsvBytes(path.filename().string(), readFileBytes(path, max_samples * 40), max_samples);
}

Grid readCsvBytes(const std::string& name, const std::string& s, std::size_t max_samples) {
  const std::string who = quoted(fs::path(name).filename().string());
  if (s.size() > max_samples * 40)
    throw TerrainError(who + ": " + countText(s.size()) + " bytes is too large for " + countText(max_samples) +
                       " samples");
  Grid g;
  std::size_t pos = 0, line_no = 0;
  int first_line = 0;
  while (pos < s.size()) {
    std::size_t eol = s.find('\n', pos);
    if (eol == std::string::npos) eol = s.size();
    std::string_view line(s.data() + pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find_first_not_of(" \t") == std::string_view::npos) continue;  // blank lines
    int count = 0;
    std::size_t at = 0;
    while (true) {
      std::size_t comma = line.find(',', at);
      std::string_view cell = line.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at);
      const auto b = cell.find_first_not_of(" \t"), e = cell.find_last_not_of(" \t");
      cell = b == std::string_view::npos ? std::string_view() : cell.substr(b, e - b + 1);
      ++count;
      const std::string where = who + " line " + countText(line_no) + ", column " + std::to_string(count);
      double v = 0.0;
      const auto [ptr, err] = std::from_chars(cell.data(), cell.data() + cell.size(), v);
      if (cell.empty() || err != std::errc() || ptr != cell.data() + cell.size())
        throw TerrainError(where + ": " + (cell.empty() ? "empty" : quoted(std::string(cell))) + " is not a number");
      if (!std::isfinite(v)) throw TerrainError(where + ": must be finite, got " + std::string(cell));
      if (std::abs(v) > 1e6) throw TerrainError(where + ": heights must be within +-1e6 m, got " + std::string(cell));
      if (g.values.size() >= max_samples)
        throw TerrainError(who + ": more than the limit of " + countText(max_samples) + " samples (4097 x 4097)");
      g.values.push_back(static_cast<float>(v));
      if (comma == std::string_view::npos) break;
      at = comma + 1;
    }
    if (g.ny == 0) {
      g.nx = count;
      first_line = static_cast<int>(line_no);
    } else if (count != g.nx) {
      throw TerrainError(who + " line " + countText(line_no) + ": has " + std::to_string(count) + " values, line " +
                         std::to_string(first_line) + " has " + std::to_string(g.nx) +
                         " (every row needs the same count)");
    }
    ++g.ny;
  }
  if (g.ny == 0) throw TerrainError(who + ": holds no numbers");
  try {
    checkBudget(g.nx, g.ny, max_samples);
  } catch (const TerrainError& e) {
    throw TerrainError(who + ": " + e.what());
  }
  return g;
}

}  // namespace groundsim::scenario
