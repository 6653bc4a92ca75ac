// What pndt-map and pndt-live do to every frame around the map update: the design §5 carriers
// (range scan -> depth, the two "id + score" label images -> labels, and back), timed per frame.
#pragma once

namespace pndt::bench
{
/// Prints the fastest of `repeat` runs of each conversion on a W x H frame with network-like
/// labels (41 classes, scores in [0, 1), a third of the pixels in instances >= 65536).
void runCarriers(int width, int height, int repeat);
}  // namespace pndt::bench
