// Dyadic refinement levels of an input box (FalStar's adaptive search, Ernst et al. 2019; the
// trees' input refinement): each input takes a fraction of its range; the corners 0 and 1 cost 0
// and n / 2^k (n odd) costs k; level l is every combination over the inputs whose costs sum to
// exactly l. Level 0 is the 2^m corners, level 1 puts one input at 1/2, level 2 one at 1/4 or 3/4
// or two at 1/2, and so on: every point of the box whose coordinates are dyadic lies on some
// level, the coarse ones first.
#pragma once
#include <cstddef>
#include <vector>

namespace hyfal {

// Level `level`'s fractions over `inputs` dimensions, row-major (inputs per combination), in a
// fixed order; each combination once.
std::vector<double> dyadic_level_fractions(std::size_t inputs, int level);

// Levels 0, 1, 2, ... concatenated until they hold at least `at_least` combinations: the order in
// which a tree node offers its refined inputs (core/search/input_grid.hpp, InputGrid::refine).
std::vector<double> dyadic_refinement_sequence(std::size_t inputs, std::size_t at_least);

}  // namespace hyfal
