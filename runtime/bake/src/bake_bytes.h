// Little-endian byte encoding for the bake file, one byte at a time so the
// file reads the same on any host. Numeric arrays of the big sections are
// stored "planar delta" (docs/bake-format.md): each element minus the one
// `stride` before it (mod 2^bits), then byte 0 of every element, byte 1 of
// every element, ... This lets zstd see the slowly varying high bytes apart
// from the noisy low bytes (a smooth basis compresses ~40 % better).
#pragma once

#include <zlib.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace relight::bake_format {

// crc32 (zlib polynomial) over any length; zlib takes 32-bit lengths.
inline uint32_t Crc32(const uint8_t* data, size_t size, uint32_t crc = 0) {
  uLong c = crc;
  while (size > 0) {
    const uInt n = size > (size_t{1} << 30) ? (uInt{1} << 30) : static_cast<uInt>(size);
    c = crc32(c, data, n);
    data += n;
    size -= n;
  }
  return static_cast<uint32_t>(c);
}

template <typename T>
using Unsigned = std::make_unsigned_t<T>;

// Stores little-endian values at a fixed place (header and TOC fields).
template <typename T>
void StoreLe(uint8_t* p, T value) {
  auto u = static_cast<Unsigned<T>>(value);
  for (size_t b = 0; b < sizeof(T); ++b) p[b] = static_cast<uint8_t>(u >> (8 * b));
}
template <typename T>
T LoadLe(const uint8_t* p) {
  Unsigned<T> u = 0;
  for (size_t b = 0; b < sizeof(T); ++b) {
    u = static_cast<Unsigned<T>>(u | Unsigned<T>{p[b]} << (8 * b));
  }
  return static_cast<T>(u);
}

// Appends to a byte vector.
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<uint8_t>* out) : out_(out) {}

  template <typename T>
  void Put(T value) {
    const size_t at = out_->size();
    out_->resize(at + sizeof(T));
    StoreLe(out_->data() + at, value);
  }
  void PutString(const std::string& s) {
    Put(static_cast<uint32_t>(s.size()));
    out_->insert(out_->end(), s.begin(), s.end());
  }
  template <typename T>
  void PutPlanar(const std::vector<T>& values, size_t stride) {
    const size_t n = values.size();
    const size_t at = out_->size();
    out_->resize(at + n * sizeof(T));
    uint8_t* planes = out_->data() + at;
    for (size_t i = 0; i < n; ++i) {
      const auto prev = i >= stride ? static_cast<Unsigned<T>>(values[i - stride]) : Unsigned<T>{0};
      const auto delta = static_cast<Unsigned<T>>(static_cast<Unsigned<T>>(values[i]) - prev);
      for (size_t b = 0; b < sizeof(T); ++b) {
        planes[b * n + i] = static_cast<uint8_t>(delta >> (8 * b));
      }
    }
  }

 private:
  std::vector<uint8_t>* out_;
};

// Reads from a bounded byte range. The first read that does not fit makes
// the reader fail (sticky); later reads do nothing, so a parser checks
// failed() once per section and reports which field ran off the end.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  bool failed() const { return !error_.empty(); }
  const std::string& error() const { return error_; }
  size_t remaining() const { return size_ - pos_; }
  size_t position() const { return pos_; }
  void Fail(const std::string& what) {
    if (error_.empty()) error_ = what;
  }

  template <typename T>
  T Get(const char* what) {
    if (!Need(sizeof(T), what)) return T{};
    const T v = LoadLe<T>(data_ + pos_);
    pos_ += sizeof(T);
    return v;
  }
  void GetString(std::string* s, uint32_t max_bytes, const char* what) {
    const uint32_t n = Get<uint32_t>(what);
    if (failed()) return;
    if (n > max_bytes) {
      Fail(std::string(what) + ": length " + std::to_string(n) + " exceeds " +
           std::to_string(max_bytes));
      return;
    }
    if (!Need(n, what)) return;
    s->assign(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
  }
  // Checks the bytes are there before allocating, so a lying count costs nothing.
  template <typename T>
  void GetPlanar(std::vector<T>* values, size_t n, size_t stride, const char* what) {
    if (failed()) return;
    if (n > remaining() / sizeof(T)) {
      Fail(std::string(what) + ": " + std::to_string(n) + " values need more than the " +
           std::to_string(remaining()) + " bytes left");
      return;
    }
    values->resize(n);
    const uint8_t* planes = data_ + pos_;
    for (size_t i = 0; i < n; ++i) {
      Unsigned<T> delta = 0;
      for (size_t b = 0; b < sizeof(T); ++b) {
        delta = static_cast<Unsigned<T>>(delta | Unsigned<T>{planes[b * n + i]} << (8 * b));
      }
      const auto prev =
          i >= stride ? static_cast<Unsigned<T>>((*values)[i - stride]) : Unsigned<T>{0};
      (*values)[i] = static_cast<T>(static_cast<Unsigned<T>>(prev + delta));
    }
    pos_ += n * sizeof(T);
  }

 private:
  bool Need(size_t n, const char* what) {
    if (failed()) return false;
    if (n > remaining()) {
      Fail(std::string(what) + ": needs " + std::to_string(n) + " bytes, " +
           std::to_string(remaining()) + " left");
      return false;
    }
    return true;
  }

  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::string error_;
};

}  // namespace relight::bake_format
