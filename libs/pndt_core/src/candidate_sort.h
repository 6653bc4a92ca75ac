// Instance matching's candidates (map instance, voxel) in order: a frame has
// thousands at 5 cm, and comparison sorting them took half of collecting them.
#pragma once

#include <vector>

#include "map_scratch.h"

namespace pndt
{
/// Sorts `v` by (instance, voxel), as std::sort with MaskCandidate::operator<
/// does (the pairs are unique, so the order is the same): least significant
/// digit first, 8 bits a pass, skipping the digits no candidate uses. `tmp` is
/// scratch.
void sortCandidates(std::vector<MaskCandidate>& v, std::vector<MaskCandidate>& tmp);

}  // namespace pndt
