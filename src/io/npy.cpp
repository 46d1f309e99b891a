// NumPy .npy reader (memory-mapped, versions 1.0-3.0) and version-1.0 writers (FORMATS.md §3).
#include "al/io/npy.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>

#include "al/core/atomic_file.hpp"
#include "al/core/error.hpp"
#include "al/core/first_touch.hpp"
#include "al/core/input_file.hpp"

namespace al {
namespace {

static_assert(std::endian::native == std::endian::little, "the .npy reader assumes a little-endian host");

// A minimal reader of the Python literal subset numpy writes in the header dict:
// strings, True/False, integers, tuples/lists, and a dict of those.
class DictParser {
 public:
  DictParser(const std::string& text, const std::string& name) : s_(text), name_(name) {}

  struct Value {
    enum Kind { kString, kBool, kInt, kSeq, kOther } kind = kOther;
    std::string str;
    bool boolean = false;
    std::int64_t integer = 0;
    std::vector<Value> items;
  };

  // Returns key -> value pairs of the top-level dict.
  std::vector<std::pair<std::string, Value>> ParseDict() {
    std::vector<std::pair<std::string, Value>> out;
    SkipSpace();
    Expect('{');
    while (true) {
      SkipSpace();
      if (Peek() == '}') { ++pos_; break; }
      Value key = ParseValue();
      if (key.kind != Value::kString) Fail("header dict key is not a string");
      SkipSpace();
      Expect(':');
      Value v = ParseValue();
      out.emplace_back(key.str, std::move(v));
      SkipSpace();
      if (Peek() == ',') { ++pos_; continue; }
      SkipSpace();
      Expect('}');
      break;
    }
    SkipSpace();
    if (pos_ != s_.size()) Fail("trailing characters after the header dict");
    return out;
  }

 private:
  [[noreturn]] void Fail(const std::string& what) const { throw FileError(name_, "bad .npy header: " + what); }
  char Peek() const { return pos_ < s_.size() ? s_[pos_] : '\0'; }
  void SkipSpace() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  void Expect(char c) {
    if (Peek() != c) Fail(std::string("expected '") + c + "'");
    ++pos_;
  }

  Value ParseValue() {
    if (++depth_ > 32) Fail("nesting too deep");
    SkipSpace();
    Value v;
    const char c = Peek();
    if (c == '\'' || c == '"') {
      ++pos_;
      v.kind = Value::kString;
      while (pos_ < s_.size() && s_[pos_] != c) {
        if (s_[pos_] == '\\') Fail("escape sequences are not supported");
        v.str += s_[pos_++];
      }
      Expect(c);
    } else if (c == '(' || c == '[') {
      const char close = c == '(' ? ')' : ']';
      ++pos_;
      v.kind = Value::kSeq;
      while (true) {
        SkipSpace();
        if (Peek() == close) { ++pos_; break; }
        v.items.push_back(ParseValue());
        SkipSpace();
        if (Peek() == ',') { ++pos_; continue; }
        SkipSpace();
        Expect(close);
        break;
      }
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-') {
      v.kind = Value::kInt;
      bool neg = false;
      if (c == '-') { neg = true; ++pos_; }
      if (!std::isdigit(static_cast<unsigned char>(Peek()))) Fail("malformed integer");
      std::uint64_t x = 0;
      while (std::isdigit(static_cast<unsigned char>(Peek()))) {
        const unsigned d = static_cast<unsigned>(s_[pos_++] - '0');
        if (x > (std::uint64_t(std::numeric_limits<std::int64_t>::max()) - d) / 10) Fail("integer too large");
        x = x * 10 + d;
      }
      if (Peek() == 'L') ++pos_;  // Python 2 long suffix written by very old numpy
      v.integer = neg ? -static_cast<std::int64_t>(x) : static_cast<std::int64_t>(x);
    } else if (s_.compare(pos_, 4, "True") == 0) {
      pos_ += 4;
      v.kind = Value::kBool;
      v.boolean = true;
    } else if (s_.compare(pos_, 5, "False") == 0) {
      pos_ += 5;
      v.kind = Value::kBool;
    } else if (c == '{') {
      Fail("nested dicts are not supported");
    } else {
      Fail("unexpected character in header dict");
    }
    --depth_;
    return v;
  }

  const std::string& s_;
  const std::string& name_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

std::size_t ItemSize(const std::string& d) { return static_cast<std::size_t>(d[1] - '0'); }

// Validates a dtype string and returns its normalised form ("f4", ...).
std::string NormaliseDescr(const std::string& descr, const std::string& name) {
  if (descr.size() < 2) throw FileError(name, "unsupported dtype '" + descr + "'");
  const char order = descr[0];
  const std::string code = descr.substr(1);
  if (order == '>') throw FileError(name, "big-endian dtype '" + descr + "' is not supported (save with '<')");
  if (code == "O" || code.rfind("O", 0) == 0)
    throw FileError(name, "object dtype (pickled data) '" + descr + "' is not supported");
  if (code[0] == 'S' || code[0] == 'U' || code[0] == 'a' || code[0] == 'V')
    throw FileError(name, "string/void dtype '" + descr + "' is not supported");
  static const char* kSingleByte[] = {"b1", "u1", "i1"};
  static const char* kMulti[] = {"i4", "i8", "u4", "u8", "f2", "f4", "f8"};
  for (const char* s : kSingleByte)
    if (code == s && (order == '|' || order == '<' || order == '=')) return code;
  for (const char* s : kMulti)
    if (code == s && (order == '<' || order == '=')) return code;
  throw FileError(name, "unsupported dtype '" + descr +
                            "' (supported: |b1 |u1 |i1 <i4 <i8 <u4 <u8 <f2 <f4 <f8)");
}

struct Mapping {
  void* addr = nullptr;
  std::size_t size = 0;
  ~Mapping() {
    if (addr && addr != MAP_FAILED) ::munmap(addr, size);
  }
};

template <typename T>
void WriteTyped(const std::string& path, const char* descr, const T* data, std::size_t n,
                const std::vector<std::int64_t>& shape) {
  if (shape.empty()) throw FileError(path, "scalar arrays (shape ()) are not supported");
  std::size_t prod = 1;
  for (std::int64_t d : shape) {
    if (d < 0) throw FileError(path, "negative dimension in shape");
    prod *= static_cast<std::size_t>(d);
  }
  if (prod != n) throw FileError(path, "data size " + std::to_string(n) + " does not match the shape");
  std::string shape_text = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) shape_text += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) shape_text += ",";  // Python's one-tuple "(N,)"
  shape_text += ")";
  std::string dict = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': " + shape_text + ", }";
  // 10 bytes of preamble + dict + padding + '\n' must be a multiple of 64.
  std::size_t total = 10 + dict.size() + 1;
  const std::size_t padded = (total + 63) / 64 * 64;
  dict.append(padded - total, ' ');
  dict += '\n';
  if (dict.size() > 65535) throw FileError(path, "header too long for .npy version 1.0");
  std::string header("\x93NUMPY\x01\x00", 8);
  header += static_cast<char>(dict.size() & 0xff);
  header += static_cast<char>(dict.size() >> 8);
  header += dict;
  WriteFileAtomically(path, [&](std::ostream& out) {
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n * sizeof(T)));
  });
}

}  // namespace

float HalfToFloat(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t exp = (h >> 10) & 0x1f;
  const std::uint32_t mant = h & 0x3ffu;
  std::uint32_t bits;
  if (exp == 0) {
    if (mant == 0) {
      bits = sign;
    } else {
      // Subnormal half: value = mant * 2^-24, exactly representable as a normal float.
      const float v = std::ldexp(static_cast<float>(mant), -24);
      return sign ? -v : v;
    }
  } else if (exp == 31) {
    bits = sign | 0x7f800000u | (mant << 13);
  } else {
    bits = sign | ((exp + 112) << 23) | (mant << 13);
  }
  return std::bit_cast<float>(bits);
}

std::size_t NpyArray::size() const {
  std::size_t n = 1;
  for (std::int64_t d : shape) n *= static_cast<std::size_t>(d);
  return n;
}

double NpyArray::At(std::size_t i) const {
  const std::uint8_t* p = data + i * item_size;
  auto load = [p](auto tag) {
    decltype(tag) v;
    std::memcpy(&v, p, sizeof(v));
    return v;
  };
  switch (descr[0]) {
    case 'b': return *p != 0 ? 1.0 : 0.0;
    case 'u':
      switch (item_size) {
        case 1: return *p;
        case 4: return static_cast<double>(load(std::uint32_t{}));
        default: return static_cast<double>(load(std::uint64_t{}));
      }
    case 'i':
      switch (item_size) {
        case 1: return static_cast<std::int8_t>(*p);
        case 4: return static_cast<double>(load(std::int32_t{}));
        default: return static_cast<double>(load(std::int64_t{}));
      }
    default:
      switch (item_size) {
        case 2: return HalfToFloat(load(std::uint16_t{}));
        case 4: return load(float{});
        default: return load(double{});
      }
  }
}

std::vector<float> NpyArray::ToFloat() const {
  const std::size_t n = size();
  std::vector<float> out(n);
  if (descr == "f4") {
    if (n) std::memcpy(out.data(), data, n * 4);
  } else {
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(At(i));
  }
  return out;
}

std::vector<double> NpyArray::ToDouble() const {
  const std::size_t n = size();
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = At(i);
  return out;
}

std::vector<std::int64_t> NpyArray::ToInt64() const {
  if (!is_integer() && !is_bool()) throw Error("npy: dtype " + descr + " is not an integer type");
  const auto n = static_cast<std::int64_t>(size());
  std::vector<std::int64_t> out;
  ReserveFirstTouched(out, static_cast<std::size_t>(n));  // 24 MB at 3M: faulted on all threads
  out.resize(static_cast<std::size_t>(n));
  // The dtype is looked at once, not per element (two string compares per label of a 3M scene
  // were a serial 5 ms), and the elements converted on all threads.
  const bool u8 = descr == "u8", i8 = descr == "i8";
#pragma omp parallel for schedule(static) if (n > 65536)
  for (std::int64_t i = 0; i < n; ++i) {
    const std::uint8_t* p = data + static_cast<std::size_t>(i) * item_size;
    std::int64_t& o = out[static_cast<std::size_t>(i)];
    if (u8) {
      std::uint64_t v;
      std::memcpy(&v, p, 8);
      // Values above int64 max cannot be indices; saturate so range checks reject them.
      o = v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
              ? std::numeric_limits<std::int64_t>::max()
              : static_cast<std::int64_t>(v);
    } else if (i8) {
      std::memcpy(&o, p, 8);
    } else {
      o = static_cast<std::int64_t>(At(static_cast<std::size_t>(i)));  // exact: <= 32-bit values fit a double
    }
  }
  return out;
}

NpyArray ParseNpy(std::shared_ptr<const void> owner, const std::uint8_t* bytes, std::size_t size,
                  const std::string& name) {
  if (size < 10 || std::memcmp(bytes, "\x93NUMPY", 6) != 0) throw FileError(name, "not a .npy file (bad magic)");
  const int major = bytes[6];
  std::size_t header_len = 0, preamble = 0;
  if (major == 1) {
    header_len = bytes[8] | (std::size_t(bytes[9]) << 8);
    preamble = 10;
  } else if (major == 2 || major == 3) {
    if (size < 12) throw FileError(name, "file too short for a .npy header");
    header_len = bytes[8] | (std::size_t(bytes[9]) << 8) | (std::size_t(bytes[10]) << 16) |
                 (std::size_t(bytes[11]) << 24);
    preamble = 12;
  } else {
    throw FileError(name, "unsupported .npy version " + std::to_string(major) + "." + std::to_string(bytes[7]));
  }
  if (header_len > size - preamble) throw FileError(name, "file too short for its .npy header (truncated)");
  const std::string text(reinterpret_cast<const char*>(bytes + preamble), header_len);
  auto dict = DictParser(text, name).ParseDict();

  bool have_descr = false, have_order = false, have_shape = false;
  NpyArray a;
  for (auto& [key, v] : dict) {
    if (key == "descr") {
      if (v.kind == DictParser::Value::kSeq) throw FileError(name, "structured dtypes are not supported");
      if (v.kind != DictParser::Value::kString) throw FileError(name, "bad .npy header: 'descr' is not a string");
      a.descr = NormaliseDescr(v.str, name);
      have_descr = true;
    } else if (key == "fortran_order") {
      if (v.kind != DictParser::Value::kBool) throw FileError(name, "bad .npy header: 'fortran_order' is not a bool");
      if (v.boolean) throw FileError(name, "fortran_order=True is not supported (save a C-ordered array)");
      have_order = true;
    } else if (key == "shape") {
      if (v.kind != DictParser::Value::kSeq) throw FileError(name, "bad .npy header: 'shape' is not a tuple");
      for (auto& d : v.items) {
        if (d.kind != DictParser::Value::kInt || d.integer < 0)
          throw FileError(name, "bad .npy header: shape entries must be non-negative integers");
        a.shape.push_back(d.integer);
      }
      have_shape = true;
    }
  }
  if (!have_descr || !have_order || !have_shape)
    throw FileError(name, "bad .npy header: missing 'descr', 'fortran_order' or 'shape'");
  if (a.shape.empty()) throw FileError(name, "scalar arrays (shape ()) are not supported");
  a.item_size = ItemSize(a.descr);
  const std::size_t available = size - preamble - header_len;
  // Overflow-safe product: stop as soon as it exceeds what the file could hold.
  std::size_t elements = 1;
  bool zero = false;
  for (std::int64_t d : a.shape) zero |= d == 0;
  if (!zero) {
    for (std::int64_t d : a.shape) {
      const auto ud = static_cast<std::size_t>(d);
      if (elements > available / ud) throw FileError(name, "data shorter than the shape requires (truncated)");
      elements *= ud;
    }
  } else {
    elements = 0;
  }
  if (elements > available / a.item_size || elements * a.item_size > available)
    throw FileError(name, "data shorter than the shape requires (truncated)");
  a.owner = std::move(owner);
  a.data = bytes + preamble + header_len;
  return a;
}

NpyArray ReadNpy(const std::string& path) {
  const int fd = OpenRegularFile(path);
  struct stat st {};
  ::fstat(fd, &st);
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size < 10) {
    ::close(fd);
    throw FileError(path, "not a .npy file (too short)");
  }
  auto mapping = std::make_shared<Mapping>();
  mapping->addr = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (mapping->addr == MAP_FAILED) throw FileError(path, "cannot memory-map");
  mapping->size = size;
  const auto* bytes = static_cast<const std::uint8_t*>(mapping->addr);
  return ParseNpy(std::shared_ptr<const void>(mapping, mapping->addr), bytes, size, path);
}

void WriteNpy(const std::string& path, const std::vector<float>& data, const std::vector<std::int64_t>& shape) {
  WriteTyped(path, "<f4", data.data(), data.size(), shape);
}
void WriteNpy(const std::string& path, const std::vector<double>& data, const std::vector<std::int64_t>& shape) {
  WriteTyped(path, "<f8", data.data(), data.size(), shape);
}
void WriteNpy(const std::string& path, const std::vector<std::int32_t>& data, const std::vector<std::int64_t>& shape) {
  WriteTyped(path, "<i4", data.data(), data.size(), shape);
}
void WriteNpy(const std::string& path, const std::vector<std::int64_t>& data, const std::vector<std::int64_t>& shape) {
  WriteTyped(path, "<i8", data.data(), data.size(), shape);
}
void WriteNpyBool(const std::string& path, const std::vector<bool>& data) {
  std::vector<std::uint8_t> bytes(data.begin(), data.end());
  WriteTyped(path, "|b1", bytes.data(), bytes.size(), {static_cast<std::int64_t>(bytes.size())});
}

}  // namespace al
