// Disjoint sets with path halving and union by size; used for components, fans and patches.
#pragma once

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace visimp {

class UnionFind {
 public:
  UnionFind() = default;
  explicit UnionFind(std::size_t n) { reset(n); }
  /// n singletons again, reusing the memory (a loop over many small sets allocates once).
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
    size_.assign(n, 1);
  }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Returns true when x and y were in different sets.
  bool unite(std::uint32_t x, std::uint32_t y) {
    x = find(x);
    y = find(y);
    if (x == y) return false;
    if (size_[x] < size_[y]) std::swap(x, y);
    parent_[y] = x;
    size_[x] += size_[y];
    return true;
  }

 private:
  std::vector<std::uint32_t> parent_, size_;
};

}  // namespace visimp
