#pragma once
/// \file
/// A plain binary codec for checkpoints: values appended little-endian to a byte string
/// and read back in the same order, every read bounds-checked. Doubles travel as their
/// bit patterns, so a state read back is bit-identical to the state written (a restarted
/// run continues exactly where the interrupted one stopped). The file framing (magic,
/// version, checksum) is io/checkpoint.hpp's; this header only encodes values.

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace cleave::physics {

static_assert(std::endian::native == std::endian::little,
              "checkpoints are written little-endian; add byte swapping for this platform");

/// A read past the end or a value out of range; `offset` is the byte where it happened.
class StateError : public std::runtime_error {
 public:
  StateError(std::size_t offset, const std::string& what)
      : std::runtime_error(what), offset_(offset) {}
  [[nodiscard]] std::size_t offset() const { return offset_; }

 private:
  std::size_t offset_;
};

class StateWriter {
 public:
  /// Integers, enums, bools and doubles, as their bytes.
  template <class T>
    requires std::is_arithmetic_v<T> || std::is_enum_v<T>
  void put(T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out_.append(bytes, sizeof(T));
  }
  void put(const Eigen::Vector3d& v) { put_raw(v.data(), 3); }
  void put(const Eigen::Matrix3d& m) { put_raw(m.data(), 9); }
  void put(const Eigen::Quaterniond& q) { put_raw(q.coeffs().data(), 4); }
  void put(std::string_view s) {
    put<std::uint64_t>(s.size());
    out_.append(s.data(), s.size());
  }
  void put(const std::string& s) { put(std::string_view(s)); }
  void put(const char* s) { put(std::string_view(s)); }
  /// A count before a sequence.
  void count(std::size_t n) { put<std::uint64_t>(n); }
  /// A vector of plain numbers.
  template <class T>
    requires std::is_arithmetic_v<T>
  void put(const std::vector<T>& v) {
    count(v.size());
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put(const std::vector<Eigen::Vector3d>& v) {
    count(v.size());
    for (const auto& x : v) put(x);
  }

  [[nodiscard]] const std::string& bytes() const { return out_; }
  [[nodiscard]] std::string take() { return std::move(out_); }
  void reserve(std::size_t n) { out_.reserve(n); }

 private:
  void put_raw(const double* p, std::size_t n) {
    out_.append(reinterpret_cast<const char*>(p), n * sizeof(double));
  }
  std::string out_;
};

class StateReader {
 public:
  /// Reads `bytes`; offsets in errors count from `base` (where `bytes` sits in its file).
  explicit StateReader(std::string_view bytes, std::size_t base = 0) : in_(bytes), base_(base) {}

  template <class T>
    requires std::is_arithmetic_v<T> || std::is_enum_v<T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, in_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  bool get_bool() {
    const auto b = get<std::uint8_t>();
    if (b > 1) fail("a flag is neither 0 nor 1");
    return b == 1;
  }
  /// An enum whose values run from 0 to `last`.
  template <class E>
    requires std::is_enum_v<E>
  E get_enum(E last) {
    const auto v = get<E>();
    using U = std::underlying_type_t<E>;
    if (static_cast<U>(v) < 0 || static_cast<U>(v) > static_cast<U>(last)) fail("an enum value is out of range");
    return v;
  }
  Eigen::Vector3d vec3() {
    Eigen::Vector3d v;
    get_raw(v.data(), 3);
    return v;
  }
  Eigen::Matrix3d mat3() {
    Eigen::Matrix3d m;
    get_raw(m.data(), 9);
    return m;
  }
  Eigen::Quaterniond quat() {
    Eigen::Quaterniond q;
    get_raw(q.coeffs().data(), 4);
    return q;
  }
  std::string string() {
    const std::size_t n = count(1);
    std::string s(in_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  /// A count of items of at least `item_bytes` each: refused when the rest of the input
  /// cannot hold that many (a corrupted count must not allocate gigabytes).
  std::size_t count(std::size_t item_bytes) {
    const auto n = get<std::uint64_t>();
    if (item_bytes > 0 && n > (in_.size() - pos_) / item_bytes) {
      fail("a count (" + std::to_string(n) + ") runs past the end of the data");
    }
    return static_cast<std::size_t>(n);
  }
  template <class T>
    requires std::is_arithmetic_v<T>
  std::vector<T> numbers() {
    const std::size_t n = count(sizeof(T));
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), in_.data() + pos_, n * sizeof(T));  // empty: data() may be null
    pos_ += n * sizeof(T);
    return v;
  }
  std::vector<Eigen::Vector3d> vec3s() {
    const std::size_t n = count(3 * sizeof(double));
    std::vector<Eigen::Vector3d> v(n);
    for (auto& x : v) x = vec3();
    return v;
  }

  [[nodiscard]] std::size_t position() const { return base_ + pos_; }
  [[nodiscard]] bool done() const { return pos_ == in_.size(); }
  [[noreturn]] void fail(const std::string& what) const {
    throw StateError(position(), "at byte " + std::to_string(position()) + ": " + what);
  }

 private:
  void need(std::size_t n) const {
    if (n > in_.size() - pos_) {
      throw StateError(base_ + in_.size(),
                       "truncated at byte " + std::to_string(base_ + in_.size()) + " (needed " +
                           std::to_string(n) + " more bytes at byte " + std::to_string(position()) + ")");
    }
  }
  void get_raw(double* p, std::size_t n) {
    need(n * sizeof(double));
    std::memcpy(p, in_.data() + pos_, n * sizeof(double));
    pos_ += n * sizeof(double);
  }
  std::string_view in_;
  std::size_t pos_ = 0;
  std::size_t base_ = 0;
};

}  // namespace cleave::physics
