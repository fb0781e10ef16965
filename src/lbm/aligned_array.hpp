#pragma once
// A page-aligned array for the fluid's bulk storage (populations, forces): pages start on 4 KiB
// boundaries, so that the layout's staggering of the Q arrays (lbm/grid.hpp) holds in memory.
#include <algorithm>
#include <cstdlib>
#include <memory>
#include <new>

namespace settle::lbm {

/// A page-aligned, uninitialised array of trivially copyable T.
template <class T>
class AlignedArray {
 public:
  AlignedArray() = default;
  explicit AlignedArray(std::size_t count) : size_(count) {
    const std::size_t bytes = (count * sizeof(T) + 4095) / 4096 * 4096;
    data_.reset(static_cast<T*>(std::aligned_alloc(4096, std::max<std::size_t>(bytes, 4096))));
    if (!data_) throw std::bad_alloc();
  }
  T* data() { return data_.get(); }
  const T* data() const { return data_.get(); }
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T[], Free> data_;
  std::size_t size_ = 0;
};

}  // namespace settle::lbm
