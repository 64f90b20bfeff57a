// Sums over a grid's nodes that give the same bits for any thread count: the nodes are cut into
// fixed blocks of node_block nodes, each block summed in index order (by whichever thread takes
// it), then the blocks' sums added in block order on one thread. A plain `omp reduction` would
// add the threads' partial sums, which differ with the thread count.
#pragma once
#include <cstddef>
#include <vector>

namespace apiclab::eol {

inline constexpr std::size_t node_block = 1024;

// Acc: default-constructible, `merge(const Acc&)`; add(acc, i) adds node i. partial holds one
// Acc per block between calls (no allocation once it has grown to the grid's block count).
template <class Acc, class Add>
Acc sum_node_blocks(std::size_t nodes, bool parallel, std::vector<Acc>& partial, Add&& add) {
  const std::ptrdiff_t blocks = std::ptrdiff_t((nodes + node_block - 1) / node_block);
  partial.resize(std::size_t(blocks));
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    Acc acc{};
    const std::size_t begin = std::size_t(b) * node_block;
    const std::size_t end = begin + node_block < nodes ? begin + node_block : nodes;
    for (std::size_t i = begin; i < end; ++i) add(acc, i);
    partial[std::size_t(b)] = acc;
  }
  Acc total{};
  for (const Acc& p : partial) total.merge(p);
  return total;
}

}  // namespace apiclab::eol
