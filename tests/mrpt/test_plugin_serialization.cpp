// Serialisation: bit-exact round trips, truncated and foreign archives, PLY and
// atomic writes.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/instance_rules.h>
#include <pndt/mrpt/map_files.h>
#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <utility>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "file_size_limit.h"
#include "observation_fixtures.h"

using namespace pndt;
namespace fs = std::filesystem;

namespace
{
uint32_t floatBits(float f)
{
    uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    return b;
}

/// A map with geometry, semantics and instances from a few viewpoints.
PanopticNDTMap::Ptr labelledMap(const MapOptions& options = {})
{
    auto m = PanopticNDTMap::Create(options);
    for (int i = 0; i < 4; ++i)
    {
        const mrpt::poses::CPose3D robot(0.0, 0.05 * i, 0.0, 0.02 * i, 0.0, 0.0);
        m->insertObservation(*fixtures::wallScan(i), robot);
        m->insertObservation(*fixtures::semanticImage(i), robot);
        m->insertObservation(*fixtures::instanceImage(i), robot);
    }
    m->insertObservation(*fixtures::wallScan(9, 2.5f), mrpt::poses::CPose3D());  // geometry only
    m->flushPending();
    return m;
}

void expectSameState(const PanopticMap& a, const PanopticMap& b)
{
    ASSERT_EQ(a.voxels().size(), b.voxels().size());
    EXPECT_EQ(a.voxels().packedKeys(), b.voxels().packedKeys());
    // Voxel and SurfaceRecord are padding-free (all 4-byte fields): compare the bytes.
    static_assert(sizeof(Voxel) == 8, "Voxel layout changed");
    static_assert(sizeof(SurfaceRecord) == 44, "SurfaceRecord layout changed");
    EXPECT_EQ(0, std::memcmp(a.voxels().voxels().data(), b.voxels().voxels().data(), sizeof(Voxel) * a.voxels().size()));
    ASSERT_EQ(a.surfaceRecords().size(), b.surfaceRecords().size());
    EXPECT_EQ(0, std::memcmp(a.surfaceRecords().data(), b.surfaceRecords().data(),
                             sizeof(SurfaceRecord) * a.surfaceRecords().size()));
    ASSERT_EQ(a.labelRecords().size(), b.labelRecords().size());
    for (size_t i = 0; i < a.labelRecords().size(); ++i)
    {
        const LabelRecord &x = a.labelRecords()[i], &y = b.labelRecords()[i];
        ASSERT_EQ(x.semantic.size(), y.semantic.size());
        EXPECT_EQ(0, std::memcmp(x.semantic.ids, y.semantic.ids, sizeof(x.semantic.ids)));
        // Every entry's weight to the bit (the file holds weights, not a
        // quantised histogram's dither phase).
        for (int j = 0; j < LabelRecord::kSemanticCapacity; ++j)
            EXPECT_EQ(floatBits(x.semantic.weight(j)), floatBits(y.semantic.weight(j))) << i << " " << j;
        EXPECT_EQ(x.n_l, y.n_l);
        EXPECT_EQ(x.instances, y.instances);
    }
    ASSERT_EQ(a.instanceRecords().size(), b.instanceRecords().size());
    for (size_t i = 0; i < a.instanceRecords().size(); ++i)
    {
        EXPECT_EQ(a.instanceRecords()[i].n_z, b.instanceRecords()[i].n_z);
        const auto &x = a.instanceRecords()[i].hist, &y = b.instanceRecords()[i].hist;
        ASSERT_EQ(x.size(), y.size());
        EXPECT_EQ(0, std::memcmp(x.ids, y.ids, sizeof(x.ids)));
        for (int j = 0; j < InstanceHistogram::kCapacity; ++j)
            EXPECT_EQ(floatBits(x.weight(j)), floatBits(y.weight(j))) << i << " " << j;
    }
    EXPECT_EQ(a.nextInstanceId(), b.nextInstanceId());
    EXPECT_EQ(a.pairEvidence(), b.pairEvidence());
    EXPECT_EQ(a.instanceFrames(), b.instanceFrames());
    const auto sa = a.semanticSpills().sorted(), sb = b.semanticSpills().sorted();
    ASSERT_EQ(sa.size(), sb.size());
    for (size_t i = 0; i < sa.size(); ++i)
    {
        EXPECT_EQ(sa[i].first, sb[i].first);
        ASSERT_EQ(sa[i].second->entries.size(), sb[i].second->entries.size());
        for (size_t j = 0; j < sa[i].second->entries.size(); ++j)
        {
            EXPECT_EQ(sa[i].second->entries[j].cls, sb[i].second->entries[j].cls);
            EXPECT_EQ(floatBits(sa[i].second->entries[j].weight), floatBits(sb[i].second->entries[j].weight));
        }
    }
}

std::vector<uint8_t> serialize(const mrpt::serialization::CSerializable& o)
{
    mrpt::io::CMemoryStream mem;
    auto a = mrpt::serialization::archiveFrom(mem);
    a << o;
    const auto* p = static_cast<const uint8_t*>(mem.getRawBufferData());
    return {p, p + mem.getTotalBytesCount()};
}

mrpt::serialization::CSerializable::Ptr deserialize(const std::vector<uint8_t>& bytes)
{
    mrpt::io::CMemoryStream mem;
    mem.assignMemoryNotOwn(bytes.data(), bytes.size());
    auto a = mrpt::serialization::archiveFrom(mem);
    mrpt::serialization::CSerializable::Ptr o;
    a >> o;
    return o;
}

fs::path tempDir()
{
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const fs::path d = fs::temp_directory_path() / ("pndt_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}
}  // namespace

TEST(PluginSerialization, RoundTripKeepsEveryVoxelFieldBitExact)
{
    const auto m = labelledMap();
    ASSERT_GT(m->core().labelRecords().size(), 0u);
    ASSERT_GT(m->core().instanceRecords().size(), 0u);
    m->renderOptions.shape = VoxelShape::Cubes;
    m->insertionOptions.label_pairing_tolerance = 0.123;
    const auto bytes = serialize(*m);
    const auto back = std::dynamic_pointer_cast<PanopticNDTMap>(deserialize(bytes));
    ASSERT_TRUE(back);
    expectSameState(m->core(), back->core());
    EXPECT_EQ(back->renderOptions.shape, VoxelShape::Cubes);
    EXPECT_DOUBLE_EQ(back->insertionOptions.label_pairing_tolerance, 0.123);
    EXPECT_EQ(back->asString(), m->asString());
    EXPECT_EQ(serialize(*back), bytes);  // and it writes the same bytes again
    // The propagated labels agree too.
    const auto ia = m->core().instances(), ib = back->core().instances();
    ASSERT_EQ(ia.size(), ib.size());
    for (size_t i = 0; i < ia.size(); ++i)
    {
        EXPECT_EQ(ia[i].id, ib[i].id);
        EXPECT_EQ(ia[i].semantic, ib[i].semantic);
        EXPECT_EQ(ia[i].voxel_count, ib[i].voxel_count);
        EXPECT_EQ(ia[i].frames_seen, ib[i].frames_seen);
        EXPECT_EQ(ia[i].confidence, ib[i].confidence);
    }
    EXPECT_FALSE(m->core().instanceFrames().empty());
}

TEST(PluginSerialization, RoundTripKeepsTheRulesBeyondThePaper)
{
    MapOptions o;
    o.split_coverage = 0.25;
    o.class_consistent_instances = false;
    o.fragment_merge_frames = 7;
    o.fragment_absorb_ratio = 0.3;
    o.label_fill_distance = 0.55;
    o.occupied_threshold = 0.25f;
    o.reset_freed_voxels = false;
    o.miss_accumulation = MissAccumulation::PerRay;
    o.instance_class_voxels = InstanceClassVoxels::TopInstance;
    o.semantic_eviction = false;
    o.void_bin = true;
    o.fragment_min_mask_pixels = 17;
    o.fragment_cover_share = 0.6;
    o.fragment_joint_factor = 1.5;
    o.max_range_along = RangeKind::Ray;
    const PanopticNDTMap m(o);
    const auto back = std::dynamic_pointer_cast<PanopticNDTMap>(deserialize(serialize(m)));
    ASSERT_TRUE(back);
    const MapOptions& b = back->core().options();
    EXPECT_EQ(b.split_coverage, 0.25);
    EXPECT_FALSE(b.class_consistent_instances);
    EXPECT_EQ(b.fragment_merge_frames, 7u);
    EXPECT_EQ(b.fragment_absorb_ratio, 0.3);
    EXPECT_EQ(b.label_fill_distance, 0.55);
    EXPECT_EQ(b.occupied_threshold, 0.25f);
    EXPECT_FALSE(b.reset_freed_voxels);
    EXPECT_EQ(b.miss_accumulation, MissAccumulation::PerRay);
    EXPECT_EQ(b.instance_class_voxels, InstanceClassVoxels::TopInstance);
    EXPECT_FALSE(b.semantic_eviction);
    EXPECT_TRUE(b.void_bin);
    EXPECT_EQ(b.fragment_min_mask_pixels, 17u);
    EXPECT_EQ(b.fragment_cover_share, 0.6);
    EXPECT_EQ(b.fragment_joint_factor, 1.5);
    EXPECT_EQ(b.max_range_along, RangeKind::Ray);
}

namespace
{
/// Reads a payload of a given serialisation version (MRPT keeps serializeFrom protected).
struct VersionReader : PanopticNDTMap
{
    using PanopticNDTMap::serializeFrom;
};

/// How version0Payload damages the label records it writes.
enum class LabelDamage
{
    None,
    EmptyEntryInside,        ///< the first record claims one semantic entry more than it holds
    UpdatesWithoutInstances,  ///< a record without instance histogram counts instance updates
    NaNWeight,                ///< the first record's strongest semantic weight is NaN
    NegativeInstanceWeight,   ///< the first instance histogram's strongest weight is -1
    WeightsOutOfOrder         ///< the first record with two semantic entries has its second above its first
};

/// The map's state in the version-0 layout (every voxel held its shape and its
/// label record index itself), written field by field as version 0 did.
std::vector<uint8_t> version0Payload(const PanopticNDTMap& m, LabelDamage damage = LabelDamage::None)
{
    const PanopticMap& map = m.core();
    const MapOptions& o = map.options();
    mrpt::io::CMemoryStream mem;
    auto a = mrpt::serialization::archiveFrom(mem);
    a << uint32_t(0x54444E50);
    a << o.voxel_size << o.max_range << o.use_ndt << uint8_t(o.ray_mode);
    a << o.log_odds_hit << o.log_odds_miss << o.log_odds_min << o.log_odds_max;
    a << o.ndt_min_samples << o.ndt_sample_cap << o.ndt_min_sigma_ratio;
    a << o.miss_min_likelihood << o.miss_likelihood_scale << o.sensor_sigma_base << o.sensor_sigma_quadratic;
    a << o.theta_l << o.theta_z << o.theta_st << o.theta_b << o.theta_m << o.theta_n << o.theta_o;
    a << o.vtou_mahalanobis_sq << o.vtou_depth_tolerance << o.query_mahalanobis_sq;
    a << uint32_t(o.classes.size());
    for (const auto& c : o.classes.classes()) a << c.name << c.is_thing;
    a << m.insertionOptions.label_pairing_tolerance << m.insertionOptions.semantic_suffix
      << m.insertionOptions.instance_suffix << uint64_t(m.insertionOptions.max_buffered_labels);
    a << uint8_t(m.renderOptions.color_mode) << uint8_t(m.renderOptions.shape) << m.renderOptions.show_free
      << m.renderOptions.point_size << uint64_t(m.renderOptions.max_ellipsoids) << m.renderOptions.ellipsoid_quantile;
    a << map.nextInstanceId();
    a << m.genericMapParams;
    const auto& voxels = map.voxels().voxels();
    const size_t n = voxels.size();
    std::vector<float> occ(n), mean(3 * n), m2(6 * n);
    std::vector<uint32_t> labels(n), count(n);
    for (size_t i = 0; i < n; ++i)
    {
        occ[i] = voxels[i].occ;
        const NdtShape& s = map.shapeOf(voxels[i]);
        count[i] = s.n;
        std::memcpy(&mean[3 * i], s.mean, sizeof(s.mean));
        std::memcpy(&m2[6 * i], s.m2, sizeof(s.m2));
        labels[i] = voxels[i].surface == kNoRecord ? kNoRecord : map.surfaceRecords()[voxels[i].surface].labels;
    }
    const auto keys = map.voxels().packedKeys();
    a << uint64_t(n);
    a.WriteBufferFixEndianness(keys.data(), n);
    a.WriteBufferFixEndianness(occ.data(), n);
    a.WriteBufferFixEndianness(labels.data(), n);
    a.WriteBufferFixEndianness(count.data(), n);
    a.WriteBufferFixEndianness(mean.data(), 3 * n);
    a.WriteBufferFixEndianness(m2.data(), 6 * n);
    const auto& recs = map.labelRecords();
    const LabelRecord* firstWithTwo = nullptr;
    for (const LabelRecord& r : recs)
        if (!firstWithTwo && r.semantic.size() >= 2) firstWithTwo = &r;
    const size_t nl = recs.size();
    a << uint64_t(nl);
    for (const LabelRecord& r : recs)
        a << uint8_t(r.semantic.size() + (damage == LabelDamage::EmptyEntryInside && &r == &recs[0]));
    for (const LabelRecord& r : recs) a.WriteBuffer(r.semantic.ids, sizeof(r.semantic.ids));
    for (const LabelRecord& r : recs)
        for (int j = 0; j < 8; ++j)
        {
            const bool nan = damage == LabelDamage::NaNWeight && &r == &recs[0] && j == 0;
            const bool raised = damage == LabelDamage::WeightsOutOfOrder && &r == firstWithTwo && j == 1;
            a << (nan ? std::nanf("") : raised ? r.semantic.weight(0) + 1.f : r.semantic.weight(j));
        }
    for (const LabelRecord& r : recs) a << r.semantic.sum();
    for (const LabelRecord& r : recs) a << stuffMass(r, o.classes);
    for (const LabelRecord& r : recs) a << r.n_l;
    const auto& irecs = map.instanceRecords();
    for (const LabelRecord& r : recs)  // n^Z is stored per label record
        a << (r.instances != kNoRecord                                ? irecs[r.instances].n_z
              : damage == LabelDamage::UpdatesWithoutInstances ? 3u
                                                               : 0u);
    for (const LabelRecord& r : recs) a << r.instances;
    a << uint64_t(irecs.size());
    for (const auto& r : irecs) a << uint8_t(r.hist.size());
    for (const auto& r : irecs) a.WriteBufferFixEndianness(r.hist.ids, 16);
    for (const auto& r : irecs)
        for (int j = 0; j < 16; ++j)
            a << (damage == LabelDamage::NegativeInstanceWeight && &r == &irecs[0] && j == 0 ? -1.f : r.hist.weight(j));
    for (const auto& r : irecs) a << r.hist.sum();
    const auto* p = static_cast<const uint8_t*>(mem.getRawBufferData());
    return {p, p + mem.getTotalBytesCount()};
}
}  // namespace

/// Reads `payload` as serialisation version `version` into `back`.
void readPayload(VersionReader& back, const std::vector<uint8_t>& payload, uint8_t version)
{
    mrpt::io::CMemoryStream mem;
    mem.assignMemoryNotOwn(payload.data(), payload.size());
    auto in = mrpt::serialization::archiveFrom(mem);
    back.serializeFrom(in, version);
}

/// The rules of the code that wrote versions 0 and 1: none of the five beyond the paper.
MapOptions versionOneRules()
{
    MapOptions o;
    o.split_coverage = 0;
    o.class_consistent_instances = false;
    o.fragment_merge_frames = 0;
    o.fragment_absorb_ratio = 0;
    o.label_fill_distance = 0;
    return o;
}

TEST(PluginSerialization, RoundTripKeepsTheSemanticSpillOfADenseHistogramMap)
{
    // The paper's h^L without eviction: ten classes per wall voxel, two of them
    // in the map's spill; the file keeps them, and a damaged spill is refused.
    MapOptions o;
    o.semantic_eviction = false;
    o.miss_accumulation = MissAccumulation::PerRay;
    auto m = PanopticNDTMap::Create(o);
    PanopticFrame f;
    f.K = {64, 48, 32.0, 32.0, 31.5, 23.5};
    f.depth.resize(64, 48, 2.0f);
    f.semantic_score.resize(64, 48, 0.9f);
    for (uint16_t c = 1; c <= 10; ++c)
    {
        f.semantic.resize(64, 48, c);
        std::fill(f.semantic.data.begin(), f.semantic.data.end(), c);
        m->core().integrate(f, Pose::Identity());
    }
    ASSERT_GT(m->core().semanticSpills().size(), 100u);
    const auto back = std::dynamic_pointer_cast<PanopticNDTMap>(deserialize(serialize(*m)));
    ASSERT_TRUE(back);
    expectSameState(m->core(), back->core());
    EXPECT_EQ(back->core().options().miss_accumulation, MissAccumulation::PerRay);
    EXPECT_FALSE(back->core().options().semantic_eviction);

    // A spilled class heavier than the record's weakest entry, or one the record holds.
    auto spills = m->core().semanticSpills().sorted();
    std::vector<std::pair<uint32_t, SemanticSpill>> bad;
    for (const auto& [li, sp] : spills) bad.emplace_back(li, *sp);
    bad[0].second.entries[0].weight = 1e6f;
    EXPECT_THROW(back->core().restoreSpills(bad), std::invalid_argument);
    bad[0].second.entries[0] = {uint8_t(m->core().labelRecords()[bad[0].first].semantic.top()), 0.1f};
    EXPECT_THROW(back->core().restoreSpills(bad), std::invalid_argument);
}

TEST(PluginSerialization, OldVersionsLoadWithTheRulesTheyWereBuiltWith)
{
    // A payload without the options added later (version 0/1 layout) written
    // from a map with today's defaults: it must not come back with them.
    const auto m = labelledMap();
    VersionReader back;
    readPayload(back, version0Payload(*m), 0);
    const MapOptions& o = back.core().options();
    EXPECT_EQ(o.split_coverage, 0.0);
    EXPECT_FALSE(o.class_consistent_instances);
    EXPECT_EQ(o.fragment_merge_frames, 0u);
    EXPECT_EQ(o.fragment_absorb_ratio, 0.0);
    EXPECT_EQ(o.label_fill_distance, 0.0);
    // Options of version 4 keep the behaviour of the code before them.
    EXPECT_EQ(o.occupied_threshold, 0.f);
    EXPECT_TRUE(o.reset_freed_voxels);
    EXPECT_EQ(o.miss_accumulation, MissAccumulation::Strongest);
    EXPECT_EQ(o.instance_class_voxels, InstanceClassVoxels::PanopticThing);
    EXPECT_TRUE(o.semantic_eviction);
    EXPECT_FALSE(o.void_bin);
    EXPECT_EQ(o.max_range_along, RangeKind::Z);  // version 5's option: z before it
}

/// The map's payload inside MRPT's object framing: [0x80 | name length][class name][version]
/// payload [0x88].
std::vector<uint8_t> payloadOf(const std::vector<uint8_t>& object, uint8_t& version)
{
    const size_t name = object.at(0) & 0x7F;
    EXPECT_EQ(std::string(object.begin() + 1, object.begin() + 1 + long(name)), "pndt::PanopticNDTMap");
    EXPECT_EQ(object.back(), 0x88);
    version = object.at(1 + name);
    return {object.begin() + 2 + long(name), object.end() - 1};
}

TEST(PluginSerialization, Version6EndsWithTheCrcOfItsPayloadAndVersion5StillReads)
{
    const auto m = labelledMap();
    uint8_t version = 0;
    const std::vector<uint8_t> v6 = payloadOf(serialize(*m), version);
    EXPECT_EQ(version, 6);
    // The last four bytes: zlib's CRC-32 of everything before them (little-endian u32).
    const std::vector<uint8_t> v5(v6.begin(), v6.end() - 4);
    const uint32_t crc = uint32_t(crc32(crc32(0L, Z_NULL, 0), v5.data(), uInt(v5.size())));
    uint32_t stored = 0;
    std::memcpy(&stored, v6.data() + v5.size(), 4);
    EXPECT_EQ(stored, crc);
    VersionReader back6, back5;
    readPayload(back6, v6, 6);
    expectSameState(m->core(), back6.core());
    readPayload(back5, v5, 5);  // maps written before the checksum load as they did
    expectSameState(m->core(), back5.core());
    // One bit of an occupancy changed: every check but the checksum passes.
    std::vector<uint8_t> bad = v6;
    bad[v5.size() / 2] ^= 1;
    VersionReader damaged;
    try
    {
        readPayload(damaged, bad, 6);
        ADD_FAILURE() << "a payload with a flipped bit loaded";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("does not match its checksum"), std::string::npos) << e.what();
    }
}

TEST(PluginSerialization, ReadsVersion0Archives)
{
    const auto m = labelledMap(versionOneRules());
    VersionReader back;
    readPayload(back, version0Payload(*m), 0);
    // Version 0 had no surface records: every voxel with a shape or labels gets
    // one, in voxel order. Voxel by voxel, everything is the same.
    const PanopticMap &a = m->core(), &b = back.core();
    ASSERT_EQ(a.voxels().size(), b.voxels().size());
    EXPECT_EQ(a.voxels().packedKeys(), b.voxels().packedKeys());
    for (uint32_t i = 0; i < a.voxels().size(); ++i)
    {
        const Voxel &x = a.voxels()[i], &y = b.voxels()[i];
        EXPECT_EQ(0, std::memcmp(&x.occ, &y.occ, sizeof(float)));
        EXPECT_EQ(0, std::memcmp(&a.shapeOf(x), &b.shapeOf(y), sizeof(NdtShape)));
        const LabelRecord *lx = a.labelsOf(x), *ly = b.labelsOf(y);
        ASSERT_EQ(lx == nullptr, ly == nullptr);
        if (lx)
        {
            EXPECT_EQ(lx - a.labelRecords().data(), ly - b.labelRecords().data());  // same pool index
        }
        EXPECT_EQ(a.panopticLabel(i), b.panopticLabel(i));
    }
    EXPECT_EQ(a.labelRecords().size(), b.labelRecords().size());
    EXPECT_EQ(a.instanceRecords().size(), b.instanceRecords().size());
    EXPECT_EQ(a.nextInstanceId(), b.nextInstanceId());
    EXPECT_EQ(back.asString(), m->asString());
}

TEST(PluginSerialization, DamagedHistogramsAreRejectedNamingTheRecord)
{
    const auto m = labelledMap();
    ASSERT_LT(m->core().labelRecords()[0].semantic.size(), LabelRecord::kSemanticCapacity);
    ASSERT_LT(m->core().instanceRecords().size(), m->core().labelRecords().size());  // some have no instances
    const auto read = [](const std::vector<uint8_t>& payload) -> std::string {
        VersionReader back;
        mrpt::io::CMemoryStream mem;
        mem.assignMemoryNotOwn(payload.data(), payload.size());
        auto in = mrpt::serialization::archiveFrom(mem);
        try
        {
            back.serializeFrom(in, 0);
        }
        catch (const std::exception& e)
        {
            return e.what();
        }
        return "no error";
    };
    EXPECT_NE(read(version0Payload(*m, LabelDamage::EmptyEntryInside)).find("label record 0 has an empty entry"),
              std::string::npos);
    const std::string e = read(version0Payload(*m, LabelDamage::UpdatesWithoutInstances));
    EXPECT_NE(e.find("counts 3 instance updates but has no instance histogram"), std::string::npos) << e;
    EXPECT_NE(e.find("truncated or corrupt"), std::string::npos) << e;
    const std::string nan = read(version0Payload(*m, LabelDamage::NaNWeight));
    EXPECT_NE(nan.find("label record 0 has a bad weight nan in entry 0"), std::string::npos) << nan;
    const std::string negative = read(version0Payload(*m, LabelDamage::NegativeInstanceWeight));
    EXPECT_NE(negative.find("instance record 0 has a bad weight -1 in entry 0"), std::string::npos) << negative;
    const auto& recs = m->core().labelRecords();
    size_t two = 0;
    while (two < recs.size() && recs[two].semantic.size() < 2) ++two;
    ASSERT_LT(two, recs.size());
    const std::string order = read(version0Payload(*m, LabelDamage::WeightsOutOfOrder));
    EXPECT_NE(order.find("label record " + std::to_string(two) + " has a bad weight"), std::string::npos) << order;
    EXPECT_NE(order.find("in entry 1 of"), std::string::npos) << order;
}

TEST(PluginSerialization, TruncatedArchivesFailWithAMessage)
{
    const auto bytes = serialize(*labelledMap());
    for (size_t cut : {size_t(3), size_t(40), bytes.size() / 3, bytes.size() / 2, bytes.size() - 1})
    {
        const std::vector<uint8_t> part(bytes.begin(), bytes.begin() + long(cut));
        try
        {
            deserialize(part);
            ADD_FAILURE() << "no error for an archive cut at " << cut << " of " << bytes.size();
        }
        catch (const std::exception& e)
        {
            // Before the class name is complete only MRPT can say what is wrong.
            if (cut >= 40)
            {
                EXPECT_NE(std::string(e.what()).find("PanopticNDTMap"), std::string::npos) << e.what();
            }
            // Inside our payload our own message says where; the last byte is
            // MRPT's end-of-object marker, reported by MRPT itself as EOF.
            if (cut > 100 && cut + 1 < bytes.size())
            {
                EXPECT_NE(std::string(e.what()).find("truncated or corrupt"), std::string::npos) << e.what();
            }
        }
    }
}

TEST(PluginSerialization, CorruptCountsAreRejectedBeforeAllocating)
{
    auto bytes = serialize(*labelledMap());
    // Flip the voxel count (first uint64 after the fixed header) to a huge value by
    // corrupting every byte after the header region; must not crash or allocate TBs.
    for (size_t i = bytes.size() / 4; i < bytes.size(); i += 7) bytes[i] ^= 0xFF;
    EXPECT_THROW(deserialize(bytes), std::exception);
}

namespace
{
/// A std::string as MRPT writes it: u32 length, then the bytes.
std::string archivedString(const std::string& text)
{
    std::string field(4, '\0');
    const uint32_t len = uint32_t(text.size());
    std::memcpy(field.data(), &len, 4);
    return field + text;
}
/// The message deserialize() throws for `bytes`, or "no error".
std::string deserializeError(const std::vector<uint8_t>& bytes)
{
    try
    {
        deserialize(bytes);
    }
    catch (const std::exception& e)
    {
        return e.what();
    }
    return "no error";
}
}  // namespace

// Issue #23, found by fuzz_map_archive: a class name's length field claiming 1.6 GB made
// MRPT's string reader allocate it (libFuzzer: out-of-memory (malloc(1632632838))).
TEST(PluginSerialization, AHugeClassNameLengthIsRefusedBeforeAllocating)
{
    const auto map = labelledMap();
    auto bytes = serialize(*map);
    const std::string field = archivedString(map->core().options().classes.classes().at(0).name);
    const size_t at = std::string(bytes.begin(), bytes.end()).find(field);
    ASSERT_NE(at, std::string::npos);
    const uint32_t huge = 1632632838u;
    std::memcpy(&bytes[at], &huge, 4);
    const std::string error = deserializeError(bytes);
    EXPECT_NE(error.find("implausible class name length 1632632838"), std::string::npos) << error;
}

// Issue #23, found by fuzz_map_archive: a bool stored as a byte other than 0 or 1 (MRPT's
// bool reader takes the byte as it is, undefined behaviour where the map uses it): the first
// class's is_thing byte (after its name) and the options' class_consistent_instances byte
// set to 246 are refused naming the field.
TEST(PluginSerialization, ABoolByteOtherThan0Or1IsRefusedNamingTheField)
{
    const auto map = labelledMap();
    const auto bytes = serialize(*map);
    const auto& classes = map->core().options().classes.classes();
    const std::string all(bytes.begin(), bytes.end());
    const std::string first = archivedString(classes.front().name);
    const size_t at = all.find(first);
    ASSERT_NE(at, std::string::npos);
    const size_t is_thing = at + first.size();
    // After the last class (its name, its is_thing byte): split_coverage (double), then
    // class_consistent_instances.
    const std::string last = archivedString(classes.back().name);
    const size_t last_at = all.find(last, at);
    ASSERT_NE(last_at, std::string::npos);
    const size_t consistent = last_at + last.size() + 1 + 8;
    for (const auto& [offset, message] : {std::pair{is_thing, "a class's is_thing is a bool holding 246"},
                                          std::pair{consistent, "class_consistent_instances is a bool holding 246"}})
    {
        ASSERT_LE(uint8_t(bytes[offset]), 1);
        auto patched = bytes;
        patched[offset] = 246;
        const std::string error = deserializeError(patched);
        EXPECT_NE(error.find(message), std::string::npos) << error;
    }
}

// Issue #23 (allocation limits): 10^9 voxels is refused by the count check; a count under
// the bound that the file does not back fails at the end of the data (read in chunks, never
// allocated up front).
TEST(PluginSerialization, AVoxelCountOfABillionIsRefusedAndUnbackedCountsFailAtTheEnd)
{
    const auto map = labelledMap();
    const auto bytes = serialize(*map);
    const uint64_t n = map->core().voxels().size();
    std::string field(8, '\0');
    std::memcpy(field.data(), &n, 8);
    const std::string all(bytes.begin(), bytes.end());
    bool refused = false, cut = false;
    for (size_t at = all.find(field); at != std::string::npos; at = all.find(field, at + 1))
    {
        for (const uint64_t claim : {uint64_t(1000000000), uint64_t(1) << 27})
        {
            auto damaged = bytes;
            std::memcpy(&damaged[at], &claim, 8);
            try
            {
                deserialize(damaged);
            }
            catch (const std::exception& e)
            {
                const std::string what = e.what();
                refused |= what.find("implausible voxel count 1000000000") != std::string::npos;
                cut |= claim == (uint64_t(1) << 27) && what.find("unexpected end of data") != std::string::npos;
            }
        }
    }
    EXPECT_TRUE(refused);
    EXPECT_TRUE(cut);
}

TEST(PluginFiles, ArchiveFileRoundTripAndForeignFiles)
{
    const fs::path dir = tempDir();
    const auto m = labelledMap();
    const std::string path = (dir / "map.pndt.gz").string();
    saveArchive(*m, path);
    EXPECT_FALSE(fs::exists(path + ".tmp." + std::to_string(::getpid())));
    const auto back = loadMapArchive(path);
    expectSameState(m->core(), back->core());

    const std::string foreign = (dir / "points.gz").string();
    saveArchive(mrpt::maps::CSimplePointsMap(), foreign);
    try
    {
        loadMapArchive(foreign);
        FAIL();
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("CSimplePointsMap"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("points.gz"), std::string::npos) << e.what();
    }
    const std::string junk = (dir / "junk.gz").string();
    std::ofstream(junk) << "this is not an MRPT archive at all";
    EXPECT_THROW(loadMapArchive(junk), std::runtime_error);
    EXPECT_THROW(loadMapArchive((dir / "missing.gz").string()), std::runtime_error);
    // Cut in its gzip trailer (the CRC and size, after the whole object): a stream read stopped
    // after the object and loaded it as complete; the gzip checks now run.
    std::string whole;
    {
        std::ifstream in(path, std::ios::binary);
        whole.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (const size_t cut : {size_t(1), size_t(4), size_t(8)})
    {
        const std::string cut_path = (dir / ("cut" + std::to_string(cut) + ".pndt.gz")).string();
        std::ofstream(cut_path, std::ios::binary) << whole.substr(0, whole.size() - cut);
        try
        {
            loadMapArchive(cut_path);
            ADD_FAILURE() << "a map file without its last " << cut << " bytes loaded";
        }
        catch (const std::runtime_error& e)
        {
            EXPECT_NE(std::string(e.what()).find(cut_path + ": not a readable map archive: the compressed data is cut"),
                      std::string::npos)
                << e.what();
        }
    }
    fs::remove_all(dir);
}

TEST(PluginFiles, AMapDamagedAndRecompressedIsRefusedByItsOwnChecksum)
{
    // gzip's CRC guards the compressed file only: a payload damaged and then recompressed
    // loaded as a map with voxels, shapes or labels elsewhere. One bit at a time, all through it.
    const fs::path dir = tempDir();
    const auto m = labelledMap();
    const std::vector<uint8_t> good = serialize(*m);
    const std::string path = (dir / "damaged.pndt.gz").string();
    auto writeGz = [&](const std::vector<uint8_t>& bytes) {
        gzFile gz = gzopen(path.c_str(), "wb");
        ASSERT_TRUE(gz);
        ASSERT_EQ(gzwrite(gz, bytes.data(), unsigned(bytes.size())), int(bytes.size()));
        ASSERT_EQ(gzclose(gz), Z_OK);
    };
    writeGz(good);
    expectSameState(m->core(), loadMapArchive(path)->core());
    size_t tried = 0, loaded = 0, by_checksum = 0;
    const size_t step = good.size() / 150 + 1;  // 150 places spread over the payload
    for (size_t i = 22; i + 1 < good.size(); i += step)  // after MRPT's class name
    {
        std::vector<uint8_t> bad = good;
        bad[i] ^= uint8_t(1u << (i % 8));
        writeGz(bad);
        ++tried;
        try
        {
            loadMapArchive(path);
            ++loaded;
        }
        catch (const std::runtime_error& e)
        {
            const std::string what = e.what();
            if (what.find("does not match its checksum") == std::string::npos) continue;
            ++by_checksum;
            EXPECT_NE(what.find(path), std::string::npos) << what;
        }
    }
    EXPECT_EQ(loaded, 0u) << "of " << tried << " maps with one bit flipped";
    EXPECT_GT(by_checksum, tried / 2) << "most flips pass every other check";
    fs::remove_all(dir);
}

TEST(PluginFiles, AtomicWriteLeavesNothingBehindOnFailure)
{
    const fs::path dir = tempDir();
    const std::string path = (dir / "out.bin").string();
    EXPECT_THROW(io::writeFileAtomically(path,
                                     [](const std::string& tmp) {
                                         std::ofstream(tmp) << "half";
                                         throw std::runtime_error("disk full");
                                     }),
                 std::runtime_error);
    EXPECT_TRUE(fs::is_empty(dir));
    fs::remove_all(dir);
}

namespace
{
struct PlyVertex
{
    uint16_t semantic;
    uint32_t instance, label;
};

/// The map's PLY, written and read back (after checking the header and the size).
std::vector<PlyVertex> plyVertices(const PanopticNDTMap& m)
{
    const fs::path dir = tempDir();
    m.saveMetricMapRepresentationToFile((dir / "map").string());
    const fs::path ply = dir / "map.ply";
    EXPECT_TRUE(fs::exists(ply));
    std::ifstream f(ply, std::ios::binary);
    std::string line, header;
    size_t vertices = 0;
    while (std::getline(f, line) && line != "end_header")
    {
        header += line + "\n";
        if (line.rfind("element vertex ", 0) == 0) vertices = std::stoul(line.substr(15));
    }
    EXPECT_EQ(vertices, m.core().occupiedCount());
    EXPECT_NE(header.find("property ushort semantic"), std::string::npos);
    EXPECT_NE(header.find("property uint instance"), std::string::npos);
    const size_t payload = fs::file_size(ply) - size_t(f.tellg());
    EXPECT_EQ(payload, vertices * (12 + 3 + 2 + 4 + 4 + 4));
    std::vector<PlyVertex> out(vertices);
    for (PlyVertex& v : out)
    {
        char rec[29];
        f.read(rec, 29);
        std::memcpy(&v.semantic, rec + 15, 2);
        std::memcpy(&v.instance, rec + 17, 4);
        std::memcpy(&v.label, rec + 21, 4);
    }
    fs::remove_all(dir);
    return out;
}
}  // namespace

TEST(PluginFiles, PlyHasOneVertexPerOccupiedVoxelWithLabels)
{
    const auto m = labelledMap();
    bool chair = false;
    for (const PlyVertex& v : plyVertices(*m))
    {
        // A single map's ids start at 1 without gaps: the label carries the id itself.
        EXPECT_EQ(v.label, (uint32_t(v.semantic) << 16) | v.instance);
        chair |= v.semantic == 5 && v.instance != 0;
    }
    EXPECT_TRUE(chair);
}

TEST(PluginFiles, APlyThatMeetsAFullDiskSaysWhy)
{
    // A file size limit fails writes with EFBIG as a full disk fails them with
    // ENOSPC (SIGXFSZ ignored). The PLY writer said "write error (disk full?)"
    // without the reason: pndt-map's full-disk check (tests/faults) failed
    // whenever a PLY met the full disk first.
    const auto m = labelledMap();
    const fs::path dir = tempDir();
    const std::string prefix = (dir / "map").string();
    std::string what;
    {
        const test_support::FileSizeLimit full(600);  // the header fits, the vertices do not
        try
        {
            m->saveMetricMapRepresentationToFile(prefix);
        }
        catch (const io::WriteError& e)
        {
            what = e.what();
        }
    }
    EXPECT_NE(what.find(prefix + ".ply"), std::string::npos) << what;
    EXPECT_NE(what.find(std::strerror(EFBIG)), std::string::npos) << what;
    EXPECT_TRUE(fs::is_empty(dir));  // no temporary left behind
    fs::remove_all(dir);
}

TEST(PluginFiles, PlyLabelsOfAMapAfterAHandOverNumberItsInstancesDensely)
{
    // A later short-term map holds an instance carried over from the map before
    // (id 2) and new ones from its own id block above 65535 (65538, ...). The
    // label's 16-bit instance field gets each instance's rank, so the labels equal
    // the first map's and no two instances share one (cutting ids to their low 16
    // bits gave 2 and 65538 the same label).
    const auto first = labelledMap();
    auto later = PanopticNDTMap::Create(MapOptions{});
    later->core().reserveInstanceIds(65536 + 1);
    for (int i = 0; i < 4; ++i)
    {
        const mrpt::poses::CPose3D robot(0.0, 0.05 * i, 0.0, 0.02 * i, 0.0, 0.0);
        later->insertObservation(*fixtures::wallScan(i), robot);
        later->insertObservation(*fixtures::semanticImage(i), robot);
        later->insertObservation(*fixtures::instanceImage(i), robot);
    }
    later->insertObservation(*fixtures::wallScan(9, 2.5f), mrpt::poses::CPose3D());
    later->flushPending();
    later->core().renameInstances([](uint32_t id) { return id == 65536 + 1 ? 2u : id; });
    const std::vector<PlyVertex> a = plyVertices(*first), b = plyVertices(*later);
    ASSERT_EQ(a.size(), b.size());
    std::map<uint32_t, uint32_t> label_of_instance;
    for (size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ(b[i].label, a[i].label);
        if (b[i].instance == 0) continue;
        EXPECT_EQ(b[i].instance, a[i].instance == 1 ? 2u : 65536 + a[i].instance);  // the same instances, renamed
        const auto [it, inserted] = label_of_instance.emplace(b[i].instance, b[i].label);
        EXPECT_EQ(it->second, b[i].label);
    }
    ASSERT_TRUE(label_of_instance.count(2));
    ASSERT_TRUE(label_of_instance.count(65536 + 2));  // the pair the 16-bit cut merged
    std::set<uint32_t> labels;
    for (const auto& [ins, label] : label_of_instance) labels.insert(label);
    EXPECT_EQ(labels.size(), label_of_instance.size());
}
