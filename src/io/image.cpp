// PNG reading/writing with libpng. libpng reports errors by longjmp; every function that calls
// libpng after setjmp holds only trivially destructible locals, so no C++ destructor is skipped.
// Errors are copied into a plain buffer and turned into al::Error by the C++ callers.
#include "al/io/image.hpp"

#include <png.h>

#include <csetjmp>
#include <cstring>
#include <fstream>
#include <sstream>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/input_file.hpp"
#include "al/core/memory_limit.hpp"

namespace al {
namespace {

struct PngErrorState {
  char message[256] = "unknown libpng error";
};

extern "C" void PngErrorFn(png_structp png, png_const_charp msg) {
  auto* st = static_cast<PngErrorState*>(png_get_error_ptr(png));
  if (st) {
    std::strncpy(st->message, msg ? msg : "libpng error", sizeof(st->message) - 1);
    st->message[sizeof(st->message) - 1] = '\0';
  }
  png_longjmp(png, 1);
}
extern "C" void PngWarningFn(png_structp, png_const_charp) {}  // library code never prints

// ---- writing -----------------------------------------------------------------------------

struct WriteBuffer {
  std::string* bytes = nullptr;
  bool failed = false;
};

extern "C" void PngWriteFn(png_structp png, png_bytep data, png_size_t len) {
  auto* buf = static_cast<WriteBuffer*>(png_get_io_ptr(png));
  bool ok = true;
  try {
    buf->bytes->append(reinterpret_cast<const char*>(data), len);
  } catch (...) {
    ok = false;
  }
  if (!ok) png_error(png, "out of memory while encoding");
}
extern "C" void PngFlushFn(png_structp) {}

// Encodes rows already in PNG byte order. Returns false with st.message set on error.
bool EncodePng(WriteBuffer* out, PngErrorState* st, int width, int height, int bit_depth, int color_type,
               const std::uint8_t* data, std::size_t row_bytes, png_bytep* rows) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, st, PngErrorFn, PngWarningFn);
  if (!png) {
    std::strcpy(st->message, "cannot create libpng write struct");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    std::strcpy(st->message, "cannot create libpng info struct");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, out, PngWriteFn, PngFlushFn);
  // zlib level 1 with the SUB filter instead of libpng's default (level 6, adaptive filter choice):
  // eval writes hundreds of PNGs and encoding dominated its I/O time. Measured on the 264 PNGs of
  // a 200k-Gaussian synth eval (renders, depth pairs, masks, overlays): 2.5 ms instead of 15.8 ms
  // per file (6.3x), 13.4 MB instead of 10.8 MB (+24%) -- docs/eval.md.
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) rows[y] = const_cast<png_bytep>(data + static_cast<std::size_t>(y) * row_bytes);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

void WriteEncoded(const std::string& path, int width, int height, int bit_depth, int color_type,
                  const std::uint8_t* data, std::size_t row_bytes) {
  std::string bytes;
  WriteBuffer out{&bytes, false};
  PngErrorState st;
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  if (!EncodePng(&out, &st, width, height, bit_depth, color_type, data, row_bytes, rows.data()))
    throw FileError(path, std::string("PNG encoding failed: ") + st.message);
  WriteFileAtomically(path, bytes);
}

void CheckSize(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0 || width > (1 << 24) || height > (1 << 24))
    throw FileError(path, "invalid image size " + std::to_string(width) + "x" + std::to_string(height));
}

// ---- reading -----------------------------------------------------------------------------

struct ReadSource {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0, pos = 0;
};

extern "C" void PngReadFn(png_structp png, png_bytep out, png_size_t len) {
  auto* src = static_cast<ReadSource*>(png_get_io_ptr(png));
  if (len > src->size - src->pos) png_error(png, "file is truncated");
  std::memcpy(out, src->data + src->pos, len);
  src->pos += len;
}

struct ReadInfo {
  png_structp png = nullptr;
  png_infop info = nullptr;
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, channels = 0;
  std::size_t row_bytes = 0;
};

// Stage 1: header and transformations. On failure the structs are destroyed.
bool ReadPngHeader(ReadInfo* ri, ReadSource* src, PngErrorState* st) {
  ri->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, st, PngErrorFn, PngWarningFn);
  if (!ri->png) {
    std::strcpy(st->message, "cannot create libpng read struct");
    return false;
  }
  ri->info = png_create_info_struct(ri->png);
  if (!ri->info) {
    png_destroy_read_struct(&ri->png, nullptr, nullptr);
    std::strcpy(st->message, "cannot create libpng info struct");
    return false;
  }
  if (setjmp(png_jmpbuf(ri->png))) {
    png_destroy_read_struct(&ri->png, &ri->info, nullptr);
    return false;
  }
  png_set_read_fn(ri->png, src, PngReadFn);
  png_set_user_limits(ri->png, 1u << 24, 1u << 24);
  png_read_info(ri->png, ri->info);
  const int color = png_get_color_type(ri->png, ri->info);
  const int depth = png_get_bit_depth(ri->png, ri->info);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(ri->png);  // + alpha when tRNS is present
  else if (depth < 8) png_set_expand_gray_1_2_4_to_8(ri->png);          // values scaled to 0..255
  png_set_interlace_handling(ri->png);
  png_read_update_info(ri->png, ri->info);
  ri->width = png_get_image_width(ri->png, ri->info);
  ri->height = png_get_image_height(ri->png, ri->info);
  ri->bit_depth = png_get_bit_depth(ri->png, ri->info);
  ri->channels = png_get_channels(ri->png, ri->info);
  ri->row_bytes = png_get_rowbytes(ri->png, ri->info);
  return true;
}

// Stage 2: pixels into `buffer` (row_bytes * height). Always destroys the structs.
bool ReadPngRows(ReadInfo* ri, std::uint8_t* buffer, png_bytep* rows, PngErrorState* st) {
  if (setjmp(png_jmpbuf(ri->png))) {
    png_destroy_read_struct(&ri->png, &ri->info, nullptr);
    return false;
  }
  for (png_uint_32 y = 0; y < ri->height; ++y) rows[y] = buffer + static_cast<std::size_t>(y) * ri->row_bytes;
  png_read_image(ri->png, rows);
  png_read_end(ri->png, nullptr);
  png_destroy_read_struct(&ri->png, &ri->info, nullptr);
  return true;
}

}  // namespace

void WritePng8(const std::string& path, const Image8& image) {
  CheckSize(path, image.width, image.height);
  int color = 0;
  switch (image.channels) {
    case 1: color = PNG_COLOR_TYPE_GRAY; break;
    case 3: color = PNG_COLOR_TYPE_RGB; break;
    case 4: color = PNG_COLOR_TYPE_RGBA; break;
    default: throw FileError(path, "PNG needs 1, 3 or 4 channels, got " + std::to_string(image.channels));
  }
  const std::size_t row = static_cast<std::size_t>(image.width) * image.channels;
  if (image.pixels.size() != row * image.height) throw FileError(path, "pixel buffer size does not match the image size");
  WriteEncoded(path, image.width, image.height, 8, color, image.pixels.data(), row);
}

void WritePng16(const std::string& path, const Image16& image) {
  CheckSize(path, image.width, image.height);
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  if (image.pixels.size() != n) throw FileError(path, "pixel buffer size does not match the image size");
  std::vector<std::uint8_t> be(2 * n);  // PNG stores 16-bit samples big-endian
  for (std::size_t i = 0; i < n; ++i) {
    be[2 * i] = static_cast<std::uint8_t>(image.pixels[i] >> 8);
    be[2 * i + 1] = static_cast<std::uint8_t>(image.pixels[i] & 0xff);
  }
  WriteEncoded(path, image.width, image.height, 16, PNG_COLOR_TYPE_GRAY, be.data(), 2 * static_cast<std::size_t>(image.width));
}

PngData ReadPng(const std::string& path) {
  const std::string bytes = ReadInputFile(path);
  return DecodePng(bytes.data(), bytes.size(), path);
}

PngData DecodePng(const void* data, std::size_t size, const std::string& path) {
  if (size < 8 || png_sig_cmp(static_cast<png_const_bytep>(data), 0, 8) != 0)
    throw FileError(path, "not a PNG file (bad signature)");
  ReadSource src{static_cast<const std::uint8_t*>(data), size, 0};
  PngErrorState st;
  ReadInfo ri;
  if (!ReadPngHeader(&ri, &src, &st)) throw FileError(path, std::string("corrupt PNG: ") + st.message);
  const std::size_t total = ri.row_bytes * ri.height;
  if (ri.width == 0 || ri.height == 0 || total > (std::size_t(1) << 32)) {
    png_destroy_read_struct(&ri.png, &ri.info, nullptr);
    throw FileError(path, "image too large or empty");
  }
  // Decoded rows plus the 16-bit values handed out: checked from the header, before decoding.
  const double need = double(total) + 2.0 * double(ri.width) * ri.height * ri.channels;
  try {
    CheckMemoryEstimate(path + ": decoding this " + std::to_string(ri.width) + "x" + std::to_string(ri.height) +
                            " PNG",
                        need);
  } catch (...) {
    png_destroy_read_struct(&ri.png, &ri.info, nullptr);
    throw;
  }
  std::vector<std::uint8_t> buffer;
  std::vector<png_bytep> rows;
  try {
    buffer.resize(total);
    rows.resize(ri.height);
  } catch (...) {
    png_destroy_read_struct(&ri.png, &ri.info, nullptr);
    throw FileError(path, "out of memory");
  }
  if (!ReadPngRows(&ri, buffer.data(), rows.data(), &st)) throw FileError(path, std::string("corrupt PNG: ") + st.message);

  PngData out;
  out.width = static_cast<int>(ri.width);
  out.height = static_cast<int>(ri.height);
  out.channels = ri.channels;
  out.bit_depth = ri.bit_depth;
  const std::size_t per_row = static_cast<std::size_t>(out.width) * out.channels;
  out.values.resize(per_row * out.height);
  for (int y = 0; y < out.height; ++y) {
    const std::uint8_t* r = buffer.data() + static_cast<std::size_t>(y) * ri.row_bytes;
    std::uint16_t* o = out.values.data() + static_cast<std::size_t>(y) * per_row;
    if (out.bit_depth == 16) {
      for (std::size_t i = 0; i < per_row; ++i) o[i] = static_cast<std::uint16_t>((r[2 * i] << 8) | r[2 * i + 1]);
    } else {
      for (std::size_t i = 0; i < per_row; ++i) o[i] = r[i];
    }
  }
  return out;
}

}  // namespace al
