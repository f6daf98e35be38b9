// 8-bit RGB PNG files through libpng's classic API. libpng reports errors by
// longjmp: the functions that call setjmp hold only trivially destructible
// locals, so a longjmp skips no destructor, and every path closes the file
// and frees libpng's structures.
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

#include "relight/render/osmesa_frame.h"

namespace relight {
namespace {

// Refuse absurd sizes from hostile files before allocating (192 MiB of RGB).
constexpr int kMaxPngSide = 32768;
constexpr uint64_t kMaxPngPixels = uint64_t{1} << 26;

// Where libpng's error handler leaves its reason before longjmp.
struct PngErrorSink {
  char reason[200];
};

void OnPngError(png_structp png, png_const_charp message) {
  auto* sink = static_cast<PngErrorSink*>(png_get_error_ptr(png));
  std::snprintf(sink->reason, sizeof sink->reason, "%s", message != nullptr ? message : "libpng error");
  png_longjmp(png, 1);
}

void OnPngWarning(png_structp, png_const_charp) {}  // warnings do not fail a read

Status IoError(const std::string& path, const char* what, const char* reason) {
  return Status(StatusCode::kIoError, StrFormat("png: %s: %s: %s", path.c_str(), what, reason));
}

// Writes rows to an open file; returns false with sink->reason set on failure.
bool WriteRows(FILE* file, png_bytep* rows, int width, int height, PngErrorSink* sink) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, OnPngError, OnPngWarning);
  if (png == nullptr) {
    std::snprintf(sink->reason, sizeof sink->reason, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(sink->reason, sizeof sink->reason, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

// What ReadRows found; filled before the pixel data is decoded.
struct PngHeader {
  png_uint_32 width;
  png_uint_32 height;
};

// Reads the file as RGB8. `rgb` and `rows` are caller-owned (their
// destructors must not be skipped by a longjmp); `rows` is filled here.
bool ReadRows(FILE* file, std::vector<uint8_t>* rgb, std::vector<png_bytep>* rows, PngHeader* header,
              PngErrorSink* sink) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, sink, OnPngError, OnPngWarning);
  if (png == nullptr) {
    std::snprintf(sink->reason, sizeof sink->reason, "out of memory");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    std::snprintf(sink->reason, sizeof sink->reason, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_user_limits(png, kMaxPngSide, kMaxPngSide);
  png_init_io(png, file);
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);

  // Any 1..16-bit gray, palette, RGB, with or without alpha, becomes RGB8.
  // Alpha is dropped, not composited: our frames are opaque.
  const png_byte color_type = png_get_color_type(png, info);
  const png_byte bit_depth = png_get_bit_depth(png, info);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
  if (bit_depth == 16) png_set_strip_16(png);
  // (Palette expansion turns a tRNS chunk into an alpha channel too.)
  if ((color_type & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS)) {
    png_set_strip_alpha(png);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);

  header->width = png_get_image_width(png, info);
  header->height = png_get_image_height(png, info);
  if (static_cast<uint64_t>(header->width) * header->height > kMaxPngPixels) {
    std::snprintf(sink->reason, sizeof sink->reason, "image %ux%u too large", header->width, header->height);
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  if (png_get_rowbytes(png, info) != static_cast<size_t>(header->width) * 3) {
    std::snprintf(sink->reason, sizeof sink->reason, "unexpected row layout after conversion to RGB8");
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  rgb->resize(static_cast<size_t>(header->width) * header->height * 3);
  rows->resize(header->height);
  for (png_uint_32 y = 0; y < header->height; ++y) {
    (*rows)[y] = rgb->data() + static_cast<size_t>(y) * header->width * 3;
  }
  png_read_image(png, rows->data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

}  // namespace

Status WritePngRgb8(const std::string& path, const uint8_t* rgb, int width, int height) {
  if (rgb == nullptr || width < 1 || height < 1 || width > kMaxPngSide || height > kMaxPngSide) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("png: %s: bad image %dx%d", path.c_str(), width, height));
  }
  std::vector<png_bytep> rows(static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    // libpng's row pointers are non-const but it only reads them when writing.
    rows[static_cast<size_t>(y)] = const_cast<png_bytep>(rgb + static_cast<size_t>(y) * width * 3);
  }
  // Write beside the target and rename, so a failed write never leaves a
  // truncated file where a good one was.
  const std::string tmp_path = path + ".tmp";
  FILE* file = std::fopen(tmp_path.c_str(), "wb");
  if (file == nullptr) return IoError(path, "cannot create", std::strerror(errno));
  PngErrorSink sink{};
  const bool written = WriteRows(file, rows.data(), width, height, &sink);
  const bool flushed = std::fflush(file) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(file) == 0;
  if (!written || !flushed || !closed) {
    std::remove(tmp_path.c_str());
    return IoError(path, "write failed", written ? std::strerror(flush_errno) : sink.reason);
  }
  if (std::rename(tmp_path.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp_path.c_str());
    return IoError(path, "rename failed", std::strerror(e));
  }
  return Status::Ok();
}

Status ReadPngRgb8(const std::string& path, std::vector<uint8_t>* rgb, int* width, int* height) {
  if (rgb == nullptr || width == nullptr || height == nullptr) {
    return Status(StatusCode::kInvalidArgument, StrFormat("png: %s: null output", path.c_str()));
  }
  FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return IoError(path, "cannot open", std::strerror(errno));
  png_byte signature[8] = {};
  if (std::fread(signature, 1, sizeof signature, file) != sizeof signature ||
      png_sig_cmp(signature, 0, sizeof signature) != 0) {
    std::fclose(file);
    return IoError(path, "read failed", "not a PNG file");
  }
  std::vector<uint8_t> pixels;
  std::vector<png_bytep> rows;
  PngHeader header{};
  PngErrorSink sink{};
  const bool ok = ReadRows(file, &pixels, &rows, &header, &sink);
  std::fclose(file);
  if (!ok) return IoError(path, "read failed", sink.reason);
  rgb->swap(pixels);
  *width = static_cast<int>(header.width);
  *height = static_cast<int>(header.height);
  return Status::Ok();
}

}  // namespace relight
