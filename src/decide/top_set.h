#pragma once
// The candidates nothing outside them beats: the Schwartz set (Schwartz 1986, *The Logic of Collective
// Choice*; the union of the source components of the "beats" graph) of a relation that need not be
// transitive or acyclic. "Faster beyond the noise" is such a relation: ties do not chain, and medians of
// paired ratios can form a cycle (a faster than b, b than c, c than a), where "the candidates nobody beats"
// is empty. The Schwartz set is never empty, and equals that set whenever there is no cycle.
#include <cstddef>
#include <functional>
#include <vector>

namespace aovar::decide {

// beats(i, j): i beats j (irreflexive; need not be transitive, asymmetric or acyclic). `pivot` is any
// member, best the one most likely to beat the rest (the fastest point): only the members it does not beat
// and those that reach them are compared with everyone, so the cost is about n x (size of that closure)
// calls, near linear when the pivot beats most. Returns the Schwartz set's indices, ascending.
std::vector<std::size_t> schwartz_set(std::size_t n, std::size_t pivot,
                                      const std::function<bool(std::size_t, std::size_t)>& beats);

}  // namespace aovar::decide
