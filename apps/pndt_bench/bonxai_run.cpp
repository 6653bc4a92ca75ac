#include "bonxai_run.h"

#include <stdexcept>

#ifdef PNDT_WITH_BONXAI
#include <bonxai_map/probabilistic_map.hpp>
#endif

namespace pndt::bench
{
#ifdef PNDT_WITH_BONXAI
bool haveBonxai() { return true; }

OccupancyRun runBonxai(const BenchFrames& b, double voxel, double max_range)
{
    Bonxai::ProbabilisticMap map(voxel);
    OccupancyRun r = timeFrames(
        b,
        [&](size_t i) {
            // The bench's points are already a std::vector of Eigen vectors, which Bonxai
            // takes as they are (OctoMap's time includes a copy into its own type).
            const Eigen::Vector3f origin = b.poses[i].translation().cast<float>();
            map.insertPointCloud(b.world_points[i], origin, max_range);
        },
        [] {});
    r.cells = map.grid().activeCellsCount();
    r.bytes_per_cell = double(map.grid().memUsage()) / double(r.cells ? r.cells : 1);
    return r;
}
#else
bool haveBonxai() { return false; }
OccupancyRun runBonxai(const BenchFrames&, double, double)
{
    throw std::logic_error("pndt-bench was built without Bonxai (configure with -DPNDT_BONXAI_DIR=<source tree>)");
}
#endif
}  // namespace pndt::bench
