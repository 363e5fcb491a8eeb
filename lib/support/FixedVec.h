//! @file FixedVec.h
//! @brief A vector of at most N elements stored inline: no heap allocation, for the per-axis
//!        data of a move (at most one element per axis), made and dropped millions of times a run.
#pragma once

#include <cassert>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <new>
#include <type_traits>

namespace iso::support {

/// Elements are trivially copyable (per-axis numbers and records): copies take only the
/// elements in use, and the unused capacity is never initialised.
template <class T, size_t N> class FixedVec {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);

public:
  FixedVec() {}
  FixedVec(std::initializer_list<T> init) {
    for (const T& v : init)
      push_back(v);
  }
  FixedVec(const FixedVec& o) : size_(o.size_) { std::uninitialized_copy(o.begin(), o.end(), data()); }
  FixedVec& operator=(const FixedVec& o) {
    if (this != &o) {
      size_ = o.size_;
      std::uninitialized_copy(o.begin(), o.end(), data());
    }
    return *this;
  }
  ~FixedVec() = default;

  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  static constexpr size_t capacity() { return N; }

  T& operator[](size_t i) {
    assert(i < size_);
    return data()[i];
  }
  const T& operator[](size_t i) const {
    assert(i < size_);
    return data()[i];
  }
  T& front() { return (*this)[0]; }
  const T& front() const { return (*this)[0]; }
  T& back() { return (*this)[size_ - 1]; }
  const T& back() const { return (*this)[size_ - 1]; }
  T* data() { return std::launder(reinterpret_cast<T*>(storage_)); }
  const T* data() const { return std::launder(reinterpret_cast<const T*>(storage_)); }
  T* begin() { return data(); }
  T* end() { return data() + size_; }
  const T* begin() const { return data(); }
  const T* end() const { return data() + size_; }

  void push_back(const T& v) {
    assert(size_ < N);
    ::new (static_cast<void*>(storage_ + size_ * sizeof(T))) T(v);
    ++size_;
  }
  void clear() { size_ = 0; }
  /// n elements, each `v` (n <= N).
  void assign(size_t n, const T& v) {
    assert(n <= N);
    size_ = 0;
    for (size_t i = 0; i < n; ++i)
      push_back(v);
  }

  friend bool operator==(const FixedVec& a, const FixedVec& b) {
    if (a.size_ != b.size_) return false;
    for (size_t i = 0; i < a.size_; ++i)
      if (!(a[i] == b[i])) return false;
    return true;
  }

private:
  alignas(T) unsigned char storage_[N * sizeof(T)];
  size_t size_ = 0;
};

} // namespace iso::support
