// The bytes of a solver's state in a checkpoint (app/checkpoint.hpp): plain values and whole
// arrays in memory layout, appended in one order and read back in the same order. The reader
// checks every length against what is left and what the fresh solver holds, so a checkpoint of
// another scene or a damaged one is refused by a StateError naming the difference, never read
// past its end.
#pragma once
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace apiclab {

struct StateError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class StateWriter {
 public:
  explicit StateWriter(std::string& out) : out_(out) {}
  template <class V>
  void value(const V& v) {
    static_assert(std::is_trivially_copyable_v<V>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof(V));
  }
  // The element count, then the elements as they lie in memory (plain values, or Eigen's
  // fixed-size vectors and matrices: arrays of scalars).
  template <class E, class A>
  void array(const std::vector<E, A>& v) {
    static_assert(std::is_trivially_destructible_v<E>);
    value(std::uint64_t(v.size()));
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(E));
  }
  void text(const std::string& s) {
    value(std::uint64_t(s.size()));
    out_.append(s);
  }
  // A section's name: the reader checks it, so a state read out of step stops at the first name.
  void tag(const char* name) { text(name); }

 private:
  std::string& out_;
};

class StateReader {
 public:
  StateReader(const char* data, std::size_t size) : at_(data), end_(data + size) {}
  template <class V>
  V value() {
    static_assert(std::is_trivially_copyable_v<V>);
    V v;
    std::memcpy(&v, take(sizeof(V)), sizeof(V));
    return v;
  }
  template <class V>
  void value(V& v) {
    v = value<V>();
  }
  // An array of any length (within what is left).
  template <class E, class A>
  void array(std::vector<E, A>& v) {
    const std::uint64_t n = value<std::uint64_t>();
    if (n > left() / sizeof(E)) throw StateError("the state ends early");
    v.resize(std::size_t(n));
    // An empty vector may hold no storage: memcpy takes no null pointer, even for 0 bytes.
    if (!v.empty())
      std::memcpy(static_cast<void*>(v.data()), take(v.size() * sizeof(E)), v.size() * sizeof(E));
  }
  // An array whose length the fresh solver already has (particles of the same scene): `what`
  // names it when the lengths differ.
  template <class E, class A>
  void same_size_array(std::vector<E, A>& v, const char* what) {
    const std::uint64_t n = value<std::uint64_t>();
    if (n != v.size())
      throw StateError(std::string("it holds ") + std::to_string(n) + " " + what +
                       ", the scene makes " + std::to_string(v.size()));
    // An empty vector may hold no storage: memcpy takes no null pointer, even for 0 bytes.
    if (!v.empty())
      std::memcpy(static_cast<void*>(v.data()), take(v.size() * sizeof(E)), v.size() * sizeof(E));
  }
  std::string text() {
    const std::uint64_t n = value<std::uint64_t>();
    if (n > left()) throw StateError("the state ends early");
    return std::string(take(std::size_t(n)), std::size_t(n));
  }
  void tag(const char* name) {
    if (text() != name) throw StateError(std::string("its state has no '") + name + "' section");
  }
  std::size_t left() const { return std::size_t(end_ - at_); }

 private:
  const char* take(std::size_t n) {
    if (n > left()) throw StateError("the state ends early");
    const char* p = at_;
    at_ += n;
    return p;
  }
  const char* at_;
  const char* end_;
};

}  // namespace apiclab
