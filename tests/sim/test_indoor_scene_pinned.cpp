// The preset rooms are what their seeds made when the documented numbers were measured
// (doc/results.md, the generated default scene): pinned by a hash of every primitive, rounded
// to 0.1 mm / 1e-4 rad. A clang build made other rooms from the same seeds (random draws as
// two arguments of one call, whose order C++ leaves open); CI builds this test with clang too
// (the fuzz build of scripts/fuzz.sh).
#include <gtest/gtest.h>
#include <pndt/sim/indoor_scene.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>

using namespace pndt::sim;

namespace
{
uint64_t mix(uint64_t h, int64_t v)  // FNV-1a over the value's bytes
{
    for (int b = 0; b < 8; ++b)
    {
        h ^= uint64_t(v >> (8 * b)) & 0xFF;
        h *= 1099511628211ull;
    }
    return h;
}
int64_t tenthMm(double x) { return std::llround(x * 1e4); }

uint64_t primitivesHash(const Scene& s)
{
    uint64_t h = 14695981039346656037ull;
    for (const Primitive& p : s.primitives)
    {
        h = mix(h, int64_t(p.kind));
        for (int a = 0; a < 3; ++a) h = mix(mix(h, tenthMm(p.center[a])), tenthMm(p.half_extent[a]));
        h = mix(mix(mix(h, tenthMm(p.yaw)), tenthMm(p.radius)), tenthMm(p.half_height));
        h = mix(mix(h, p.semantic), p.instance);
    }
    return h;
}
}  // namespace

TEST(IndoorScenePinned, EveryPresetIsTheRoomItsSeedMade)
{
    const std::map<std::string, std::pair<size_t, uint64_t>> pinned = {
#include "indoor_scene_pins.inc"
    };
    for (const std::string& name : indoorScenePresetNames())
    {
        const Scene s = makeIndoorScene(indoorScenePreset(name));
        const auto it = pinned.find(name);
        if (it == pinned.end() || it->second != std::pair(s.primitives.size(), primitivesHash(s)))
            std::printf("this build's line for indoor_scene_pins.inc:\n    {\"%s\", {%zu, 0x%016llxull}},\n",
                        name.c_str(), s.primitives.size(), static_cast<unsigned long long>(primitivesHash(s)));
        if (it == pinned.end())
        {
            ADD_FAILURE() << "no pin for preset " << name;
            continue;
        }
        EXPECT_EQ(s.primitives.size(), it->second.first) << name;
        EXPECT_EQ(primitivesHash(s), it->second.second) << name << ": not the room this seed made before";
    }
}
