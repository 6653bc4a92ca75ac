// Versioned MRPT serialisation of PanopticNDTMap. Every voxel field is written
// raw, so a round trip is bit-exact.
//
// Version 6 (written): version 5, then the CRC-32 (u32, zlib's) of every byte of
// it from the magic on: a payload damaged and then recompressed (or stored plain)
// passes gzip's own check, and must not load as a map with voxels elsewhere.
// Version 5 (read): version 4 with the map option max_range_along (u8: 0 z,
// 1 ray length) right after fragment_joint_factor.
// Version 4 (read): version 3 with the map options occupied_threshold (f32),
// reset_freed_voxels (bool), miss_accumulation (u8), instance_class_voxels (u8),
// semantic_eviction (bool), void_bin (bool), fragment_min_mask_pixels (u32),
// fragment_cover_share (f64) and fragment_joint_factor (f64) after
// label_fill_distance, and at the end the semantic spills (classes of h^L beyond
// a full label record, semantic_eviction = false): count (u64), label record
// (u32 array), entries per spill (u8 array), then all entries' classes (u8) and
// weights (f32). The stored h^L sum and stuff mass include the spill. Then the
// frames each instance was seen in: count (u64), ids and frames (u32 arrays).
// A map of an older version reads with the rules it was built with: the options
// its version did not store did not exist then, so they take the values that
// reproduce that code (version 1: the three matching rules off; version <= 2:
// the two finalisation steps off; version <= 3: the defaults of version 4,
// which are that code's behaviour).
// Version 3 (read): version 2 with the map options fragment_absorb_ratio
// (f64) and label_fill_distance (f64) after fragment_merge_frames.
// Version 2 (read): version 1 with the map options split_coverage (f64),
// class_consistent_instances (bool) and fragment_merge_frames (u32) after the
// class set, and at the end the fragment evidence: count (u64), then instance a,
// instance b, joint, apart (u32 arrays).
// Version 1 layout (read): magic "PNDT", map options, class set, insertion
// and render options, next instance id, generic map parameters, then
// struct-of-arrays blocks, each preceded by its element count:
//  - voxels: packed key (u64), occupancy (f32), surface record (u32);
//  - surface records: NDT sample count (u32), mean (3 x f32), scatter (6 x f32),
//    label record (u32);
//  - label records and instance records, as in version 0.
// Version 0 (read): the same, but the voxel block held each voxel's label record
// (u32), count, mean and scatter itself; reading gives every voxel that has a
// shape or labels a surface record, in voxel order.
#include <fmt/format.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/instance_rules.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include "crc_archive.h"

#include <cmath>
#include <algorithm>
#include <cstring>

using mrpt::serialization::CArchive;

namespace pndt
{
namespace
{
/// A map file that is whole but holds what this version refuses (not damage: no "corrupt").
struct NotAcceptedContent : std::runtime_error
{
    using std::runtime_error::runtime_error;
};

constexpr uint32_t kMagic = 0x54444E50;  // "PNDT"
// Bounds against garbage counts: refuse before allocating. 2^28 voxels would be a map of
// tens of GB; a file claiming more is damaged (doc/hardening.md). Counts below the bound
// are still only allocated as their bytes arrive (readArray).
constexpr uint64_t kMaxVoxels = 1ull << 28;
constexpr uint32_t kMaxNameLength = 4096;  ///< class names, label suffixes

void writeOptions(CArchive& a, const MapOptions& o)
{
    a << o.voxel_size << o.max_range << o.use_ndt << uint8_t(o.ray_mode);
    a << o.log_odds_hit << o.log_odds_miss << o.log_odds_min << o.log_odds_max;
    a << o.ndt_min_samples << o.ndt_sample_cap << o.ndt_min_sigma_ratio;
    a << o.miss_min_likelihood << o.miss_likelihood_scale << o.sensor_sigma_base << o.sensor_sigma_quadratic;
    a << o.theta_l << o.theta_z << o.theta_st << o.theta_b << o.theta_m << o.theta_n << o.theta_o;
    a << o.vtou_mahalanobis_sq << o.vtou_depth_tolerance << o.query_mahalanobis_sq;
    a << uint32_t(o.classes.size());
    for (const auto& c : o.classes.classes()) a << c.name << c.is_thing;
    a << o.split_coverage << o.class_consistent_instances << o.fragment_merge_frames;
    a << o.fragment_absorb_ratio << o.label_fill_distance;
    a << o.occupied_threshold << o.reset_freed_voxels << uint8_t(o.miss_accumulation)
      << uint8_t(o.instance_class_voxels) << o.semantic_eviction << o.void_bin << o.fragment_min_mask_pixels
      << o.fragment_cover_share << o.fragment_joint_factor;
    a << uint8_t(o.max_range_along == RangeKind::Ray ? 1 : 0);
}

/// A std::string as MRPT writes it (u32 length, bytes), read with a bound on the length:
/// MRPT's own reader allocates and zero-fills whatever length the file claims (found by
/// fuzz_map_archive: "out-of-memory (malloc(1632632838))").
std::string readString(CArchive& a, const char* what)
{
    uint32_t len = 0;
    a >> len;
    if (len > kMaxNameLength) throw std::runtime_error(fmt::format("implausible {} length {}", what, len));
    std::string s(len, '\0');
    if (len && a.ReadBuffer(s.data(), len) != len) throw std::runtime_error("unexpected end of data");
    return s;
}

/// A bool as MRPT writes it (one byte), refused unless 0 or 1: MRPT's operator>>(bool&)
/// reads the byte into the bool as it is, and any other value is undefined behaviour where
/// the bool is used (found by fuzz_map_archive: "load of value 246, which is not a valid
/// value for type 'bool'" in the propagation).
bool readBool(CArchive& a, const char* what)
{
    uint8_t b = 0;
    a >> b;
    if (b > 1) throw std::runtime_error(fmt::format("{} is a bool holding {}", what, unsigned(b)));
    return b == 1;
}

MapOptions readOptions(CArchive& a, uint8_t version)
{
    MapOptions o;
    uint8_t ray = 0;
    a >> o.voxel_size >> o.max_range;
    o.use_ndt = readBool(a, "use_ndt");
    a >> ray;
    o.ray_mode = ray == 0 ? RayMode::Merged : RayMode::PerPixel;
    a >> o.log_odds_hit >> o.log_odds_miss >> o.log_odds_min >> o.log_odds_max;
    a >> o.ndt_min_samples >> o.ndt_sample_cap >> o.ndt_min_sigma_ratio;
    a >> o.miss_min_likelihood >> o.miss_likelihood_scale >> o.sensor_sigma_base >> o.sensor_sigma_quadratic;
    a >> o.theta_l >> o.theta_z >> o.theta_st >> o.theta_b >> o.theta_m >> o.theta_n >> o.theta_o;
    a >> o.vtou_mahalanobis_sq >> o.vtou_depth_tolerance >> o.query_mahalanobis_sq;
    uint32_t n = 0;
    a >> n;
    if (n == 0 || n > 255) throw std::runtime_error(fmt::format("class set of {} classes", n));
    std::vector<ClassSet::Class> classes(n);
    for (auto& c : classes)
    {
        c.name = readString(a, "class name");
        c.is_thing = readBool(a, "a class's is_thing");
    }
    try
    {
        o.classes = ClassSet(std::move(classes));
    }
    catch (const std::invalid_argument& e)
    {
        // Not damage: a set this version refuses (a map written by an earlier one, whose config
        // had a name twice or a class 0 other than void).
        throw NotAcceptedContent(fmt::format("the map's class set is not one this version takes ({}): written by an "
                                             "earlier version, or damaged",
                                             e.what()));
    }
    // Older maps keep the rules they were built with (see the top of this file).
    if (version >= 2)
    {
        a >> o.split_coverage;
        o.class_consistent_instances = readBool(a, "class_consistent_instances");
        a >> o.fragment_merge_frames;
    }
    else
    {
        o.split_coverage = 0;
        o.class_consistent_instances = false;
        o.fragment_merge_frames = 0;
    }
    if (version >= 3)
        a >> o.fragment_absorb_ratio >> o.label_fill_distance;
    else
        o.fragment_absorb_ratio = o.label_fill_distance = 0;
    if (version >= 4)
    {
        uint8_t misses = 0, class_voxels = 0;
        a >> o.occupied_threshold;
        o.reset_freed_voxels = readBool(a, "reset_freed_voxels");
        a >> misses >> class_voxels;
        o.semantic_eviction = readBool(a, "semantic_eviction");
        o.void_bin = readBool(a, "void_bin");
        a >> o.fragment_min_mask_pixels >> o.fragment_cover_share >> o.fragment_joint_factor;
        if (misses > 1 || class_voxels > 1)
            throw std::runtime_error(fmt::format("unknown miss_accumulation {} or instance_class_voxels {}",
                                                 misses, class_voxels));
        o.miss_accumulation = MissAccumulation(misses);
        o.instance_class_voxels = InstanceClassVoxels(class_voxels);
    }
    if (version >= 5)
    {
        uint8_t along = 0;
        a >> along;
        if (along > 1) throw std::runtime_error(fmt::format("unknown max_range_along {}", along));
        o.max_range_along = along ? RangeKind::Ray : RangeKind::Z;
    }
    o.validate();
    return o;
}

template <typename T>
void writeArray(CArchive& a, const std::vector<T>& v)
{
    if (!v.empty()) a.WriteBufferFixEndianness(v.data(), v.size());
}
template <typename T>
void readArray(CArchive& a, std::vector<T>& v, size_t n)
{
    // Grown as the bytes arrive (4 MiB at a time): a count the file does not back fails at
    // the end of the data having allocated no more than the file holds plus one chunk.
    constexpr size_t kChunk = std::max<size_t>(1, (size_t(4) << 20) / sizeof(T));
    v.clear();
    v.reserve(std::min(n, kChunk));
    for (size_t done = 0; done < n;)
    {
        const size_t k = std::min(kChunk, n - done);
        v.resize(done + k);
        if (a.ReadBufferFixEndianness(v.data() + done, k) != k * sizeof(T))
            throw std::runtime_error("unexpected end of data");
        done += k;
    }
}
/// Entries in use of a stored histogram of `capacity` whose count is `size`:
/// ids before it must be set (0 marks a free entry), those after it are ignored.
template <typename Id>
int checkedEntries(uint8_t size, int capacity, const Id* ids, const char* what, size_t index)
{
    if (size > capacity) throw std::runtime_error(fmt::format("{} {} has {} entries", what, index, size));
    for (int j = 0; j < size; ++j)
        if (ids[j] == 0) throw std::runtime_error(fmt::format("{} {} has an empty entry {} of {}", what, index, j, size));
    return size;
}

/// Sets a histogram's weights from the file: finite, >= 0 and in the
/// histogram's order (largest first), or the record is damaged.
template <typename H>
void setCheckedWeights(H& h, int used, const float* w, const char* what, size_t index)
{
    for (int j = 0; j < used; ++j)
    {
        if (!(w[j] >= 0) || !std::isfinite(w[j]) || (j > 0 && w[j] > w[j - 1]))
            throw std::runtime_error(fmt::format("{} {} has a bad weight {} in entry {} of {}", what, index, w[j], j, used));
        h.setWeight(j, w[j]);
    }
}

uint64_t readCount(CArchive& a, const char* what, uint64_t max)
{
    uint64_t n = 0;
    a >> n;
    if (n > max) throw std::runtime_error(fmt::format("implausible {} count {}", what, n));
    return n;
}
}  // namespace

uint8_t PanopticNDTMap::serializeGetVersion() const { return 6; }

void PanopticNDTMap::serializeTo(CArchive& raw_out) const
{
    CrcArchive out(raw_out);  // every byte below counts into the checksum written last
    out << kMagic;
    writeOptions(out, map_.options());
    out << insertionOptions.label_pairing_tolerance << insertionOptions.semantic_suffix
        << insertionOptions.instance_suffix << uint64_t(insertionOptions.max_buffered_labels);
    out << uint8_t(renderOptions.color_mode) << uint8_t(renderOptions.shape) << renderOptions.show_free
        << renderOptions.point_size << uint64_t(renderOptions.max_ellipsoids) << renderOptions.ellipsoid_quantile;
    out << map_.nextInstanceId();
    out << genericMapParams;

    // Voxels and surface records, as parallel arrays of plain numbers.
    const auto& voxels = map_.voxels().voxels();
    const size_t n = voxels.size();
    std::vector<float> occ(n);
    std::vector<uint32_t> surface(n);
    for (size_t i = 0; i < n; ++i)
    {
        occ[i] = voxels[i].occ;
        surface[i] = voxels[i].surface;
    }
    out << uint64_t(n);
    writeArray(out, map_.voxels().packedKeys());
    writeArray(out, occ);
    writeArray(out, surface);

    const auto& surfaces = map_.surfaceRecords();
    const size_t ns = surfaces.size();
    std::vector<uint32_t> count(ns), s_labels(ns);
    std::vector<float> mean(3 * ns), m2(6 * ns);
    for (size_t i = 0; i < ns; ++i)
    {
        const SurfaceRecord& r = surfaces[i];
        count[i] = r.shape.n;
        s_labels[i] = r.labels;
        std::memcpy(&mean[3 * i], r.shape.mean, sizeof(r.shape.mean));
        std::memcpy(&m2[6 * i], r.shape.m2, sizeof(r.shape.m2));
    }
    out << uint64_t(ns);
    writeArray(out, count);
    writeArray(out, mean);
    writeArray(out, m2);
    writeArray(out, s_labels);

    const auto& recs = map_.labelRecords();
    const auto& inst_recs = map_.instanceRecords();
    constexpr int SC = LabelRecord::kSemanticCapacity;
    const size_t nl = recs.size();
    std::vector<uint8_t> sem_size(nl), sem_ids(SC * nl);
    std::vector<float> sem_w(SC * nl), sem_sum(nl), stuff(nl);
    std::vector<uint32_t> n_l(nl), n_z(nl), inst(nl);
    for (size_t i = 0; i < nl; ++i)
    {
        const LabelRecord& r = recs[i];
        sem_size[i] = uint8_t(r.semantic.size());
        std::memcpy(&sem_ids[SC * i], r.semantic.ids, SC);
        for (int j = 0; j < SC; ++j) sem_w[SC * i + size_t(j)] = r.semantic.weight(j);
        // Derived; kept in the format for its readers. The whole h^L, spill included.
        const SemanticSpill* spill = map_.semanticSpills().find(uint32_t(i));
        sem_sum[i] = semanticMass(r, spill);
        stuff[i] = stuffMass(r, map_.options().classes, spill);
        n_l[i] = r.n_l;
        n_z[i] = r.instances != kNoRecord && r.instances < inst_recs.size() ? inst_recs[r.instances].n_z : 0;
        inst[i] = r.instances;
    }
    out << uint64_t(nl);
    writeArray(out, sem_size);
    writeArray(out, sem_ids);
    writeArray(out, sem_w);
    writeArray(out, sem_sum);
    writeArray(out, stuff);
    writeArray(out, n_l);
    writeArray(out, n_z);
    writeArray(out, inst);

    const auto& irecs = map_.instanceRecords();
    constexpr int IC = 16;
    const size_t ni = irecs.size();
    std::vector<uint8_t> i_size(ni);
    std::vector<uint32_t> i_ids(IC * ni);
    std::vector<float> i_w(IC * ni), i_sum(ni);
    for (size_t i = 0; i < ni; ++i)
    {
        const auto& h = irecs[i].hist;
        i_size[i] = uint8_t(h.size());
        std::memcpy(&i_ids[IC * i], h.ids, IC * sizeof(uint32_t));
        for (int j = 0; j < IC; ++j) i_w[IC * i + size_t(j)] = h.weight(j);
        i_sum[i] = h.sum();
    }
    out << uint64_t(ni);
    writeArray(out, i_size);
    writeArray(out, i_ids);
    writeArray(out, i_w);
    writeArray(out, i_sum);

    // Version 2: fragment evidence, as parallel u32 arrays.
    const auto ev = map_.pairEvidence();
    std::vector<uint32_t> ev_a, ev_b, ev_joint, ev_apart;
    for (const auto& e : ev)
    {
        ev_a.push_back(e.a);
        ev_b.push_back(e.b);
        ev_joint.push_back(e.joint);
        ev_apart.push_back(e.apart);
    }
    out << uint64_t(ev.size());
    writeArray(out, ev_a);
    writeArray(out, ev_b);
    writeArray(out, ev_joint);
    writeArray(out, ev_apart);

    // Version 4: semantic spills.
    std::vector<uint32_t> sp_record;
    std::vector<uint8_t> sp_count, sp_cls;
    std::vector<float> sp_w;
    for (const auto& [li, spill] : map_.semanticSpills().sorted())
    {
        sp_record.push_back(li);
        sp_count.push_back(uint8_t(spill->entries.size()));
        for (const auto& e : spill->entries)
        {
            sp_cls.push_back(e.cls);
            sp_w.push_back(e.weight);
        }
    }
    out << uint64_t(sp_record.size()) << uint64_t(sp_cls.size());
    writeArray(out, sp_record);
    writeArray(out, sp_count);
    writeArray(out, sp_cls);
    writeArray(out, sp_w);

    // Version 4: frames seen per instance.
    std::vector<uint32_t> fr_id, fr_n;
    for (const auto& [id, n] : map_.instanceFrames())
    {
        fr_id.push_back(id);
        fr_n.push_back(n);
    }
    out << uint64_t(fr_id.size());
    writeArray(out, fr_id);
    writeArray(out, fr_n);

    // Version 6: the checksum of all of the above.
    raw_out << out.crc();
}

void PanopticNDTMap::serializeFrom(CArchive& raw_in, uint8_t version)
{
    CrcArchive crc_in(raw_in);  // version 6 on: the bytes read are checked against the stored CRC
    CArchive& in = version >= 6 ? static_cast<CArchive&>(crc_in) : raw_in;
    switch (version)
    {
        case 0:
        case 1:
        case 2:
        case 3:
        case 4:
        case 5:
        case 6:
        {
            const char* stage = "header";
            try
            {
                uint32_t magic = 0;
                in >> magic;
                if (magic != kMagic) throw std::runtime_error("not a PanopticNDTMap payload (bad magic)");
                stage = "options";
                MapOptions o = readOptions(in, version);
                InsertionOptions io;
                uint64_t max_buf = 0;
                in >> io.label_pairing_tolerance;
                io.semantic_suffix = readString(in, "label suffix");
                io.instance_suffix = readString(in, "label suffix");
                in >> max_buf;
                io.max_buffered_labels = size_t(max_buf);
                RenderOptions ro;
                uint8_t mode = 0, shape = 0;
                uint64_t max_ell = 0;
                in >> mode >> shape >> ro.show_free >> ro.point_size >> max_ell >> ro.ellipsoid_quantile;
                if (mode > 2 || shape > 2) throw std::runtime_error("bad render options");
                ro.color_mode = ColorMode(mode);
                ro.shape = VoxelShape(shape);
                ro.max_ellipsoids = size_t(max_ell);
                uint32_t next_id = 1;
                in >> next_id;
                mrpt::maps::TMapGenericParams gp;
                in >> gp;

                stage = "voxels";
                const size_t n = readCount(in, "voxel", kMaxVoxels);
                std::vector<uint64_t> keys;
                std::vector<SurfaceRecord> surfaces;
                readArray(in, keys, n);
                std::vector<float> occ;
                readArray(in, occ, n);
                std::vector<Voxel> voxels(n);  // once the file has backed the count
                for (size_t i = 0; i < n; ++i) voxels[i].occ = occ[i];
                if (version == 0)
                {
                    std::vector<float> mean, m2;
                    std::vector<uint32_t> labels, count;
                    readArray(in, labels, n);
                    readArray(in, count, n);
                    readArray(in, mean, 3 * n);
                    readArray(in, m2, 6 * n);
                    for (size_t i = 0; i < n; ++i)
                    {
                        SurfaceRecord r;
                        r.labels = labels[i];
                        r.shape.n = count[i];
                        std::memcpy(r.shape.mean, &mean[3 * i], sizeof(r.shape.mean));
                        std::memcpy(r.shape.m2, &m2[6 * i], sizeof(r.shape.m2));
                        bool used = r.labels != kNoRecord || r.shape.n != 0;
                        for (float x : r.shape.mean) used |= x != 0.f;
                        for (float x : r.shape.m2) used |= x != 0.f;
                        if (!used) continue;
                        voxels[i].surface = uint32_t(surfaces.size());
                        surfaces.push_back(r);
                    }
                }
                else
                {
                    std::vector<uint32_t> surface;
                    readArray(in, surface, n);
                    for (size_t i = 0; i < n; ++i) voxels[i].surface = surface[i];
                    stage = "surface records";
                    const size_t ns = readCount(in, "surface record", n);
                    std::vector<uint32_t> count, s_labels;
                    std::vector<float> mean, m2;
                    readArray(in, count, ns);
                    readArray(in, mean, 3 * ns);
                    readArray(in, m2, 6 * ns);
                    readArray(in, s_labels, ns);
                    surfaces.resize(ns);
                    for (size_t i = 0; i < ns; ++i)
                    {
                        SurfaceRecord& r = surfaces[i];
                        r.shape.n = count[i];
                        r.labels = s_labels[i];
                        std::memcpy(r.shape.mean, &mean[3 * i], sizeof(r.shape.mean));
                        std::memcpy(r.shape.m2, &m2[6 * i], sizeof(r.shape.m2));
                    }
                }

                stage = "label records";
                constexpr int SC = LabelRecord::kSemanticCapacity;
                const size_t nl = readCount(in, "label record", n);
                std::vector<uint8_t> sem_size, sem_ids;
                std::vector<float> sem_w, sem_sum, stuff;
                std::vector<uint32_t> n_l, n_z, inst;
                readArray(in, sem_size, nl);
                readArray(in, sem_ids, SC * nl);
                readArray(in, sem_w, SC * nl);
                readArray(in, sem_sum, nl);  // sums are derived from the entries: read past
                readArray(in, stuff, nl);
                readArray(in, n_l, nl);
                readArray(in, n_z, nl);
                readArray(in, inst, nl);
                std::vector<LabelRecord> recs(nl);
                for (size_t i = 0; i < nl; ++i)
                {
                    LabelRecord& r = recs[i];
                    const int used = checkedEntries(sem_size[i], SC, &sem_ids[SC * i], "label record", i);
                    std::memcpy(r.semantic.ids, &sem_ids[SC * i], size_t(used));
                    setCheckedWeights(r.semantic, used, &sem_w[SC * i], "label record", i);
                    r.n_l = n_l[i];
                    r.instances = inst[i];
                }

                stage = "instance records";
                constexpr int IC = 16;
                const size_t ni = readCount(in, "instance record", nl);
                std::vector<uint8_t> i_size;
                std::vector<uint32_t> i_ids;
                std::vector<float> i_w, i_sum;
                readArray(in, i_size, ni);
                readArray(in, i_ids, IC * ni);
                readArray(in, i_w, IC * ni);
                readArray(in, i_sum, ni);
                std::vector<InstanceRecord> irecs(ni);
                for (size_t i = 0; i < ni; ++i)
                {
                    auto& h = irecs[i].hist;
                    const int used = checkedEntries(i_size[i], IC, &i_ids[IC * i], "instance record", i);
                    std::memcpy(h.ids, &i_ids[IC * i], size_t(used) * sizeof(uint32_t));
                    setCheckedWeights(h, used, &i_w[IC * i], "instance record", i);
                }
                // n^Z is stored with the label record (format v0-v3) and kept
                // with the instance histogram, the only place it can grow.
                for (size_t i = 0; i < nl; ++i)
                {
                    if (n_z[i] == 0) continue;
                    if (inst[i] >= ni)
                        throw std::runtime_error(fmt::format(
                            "label record {} counts {} instance updates but has no instance histogram", i, n_z[i]));
                    irecs[inst[i]].n_z = n_z[i];
                }

                std::vector<PanopticMap::PairEvidence> evidence;
                if (version >= 2)
                {
                    stage = "fragment evidence";
                    const size_t ne = readCount(in, "pair evidence", kMaxVoxels);
                    std::vector<uint32_t> ev_a, ev_b, ev_joint, ev_apart;
                    readArray(in, ev_a, ne);
                    readArray(in, ev_b, ne);
                    readArray(in, ev_joint, ne);
                    readArray(in, ev_apart, ne);
                    for (size_t i = 0; i < ne; ++i) evidence.push_back({ev_a[i], ev_b[i], ev_joint[i], ev_apart[i]});
                }

                std::vector<std::pair<uint32_t, SemanticSpill>> spills;
                if (version >= 4)
                {
                    stage = "semantic spills";
                    const size_t ns = readCount(in, "semantic spill", kMaxVoxels);
                    const size_t ne = readCount(in, "semantic spill entry", 256 * uint64_t(ns));
                    std::vector<uint32_t> sp_record;
                    std::vector<uint8_t> sp_count, sp_cls;
                    std::vector<float> sp_w;
                    readArray(in, sp_record, ns);
                    readArray(in, sp_count, ns);
                    readArray(in, sp_cls, ne);
                    readArray(in, sp_w, ne);
                    size_t e = 0;
                    for (size_t i = 0; i < ns; ++i)
                    {
                        if (sp_count[i] == 0 || e + sp_count[i] > ne)
                            throw std::runtime_error(fmt::format("semantic spill {} claims {} of {} entries left", i,
                                                                 sp_count[i], ne - e));
                        SemanticSpill sp;
                        for (size_t k = 0; k < sp_count[i]; ++k, ++e) sp.entries.push_back({sp_cls[e], sp_w[e]});
                        spills.emplace_back(sp_record[i], std::move(sp));
                    }
                    if (e != ne) throw std::runtime_error(fmt::format("{} semantic spill entries left over", ne - e));
                }
                std::vector<std::pair<uint32_t, uint32_t>> instance_frames;
                if (version >= 4)
                {
                    stage = "instance frames";
                    const size_t nf = readCount(in, "instance frames", kMaxVoxels);
                    std::vector<uint32_t> fr_id, fr_n;
                    readArray(in, fr_id, nf);
                    readArray(in, fr_n, nf);
                    for (size_t i = 0; i < nf; ++i) instance_frames.emplace_back(fr_id[i], fr_n[i]);
                }

                if (version >= 6)
                {
                    stage = "checksum";
                    const uint32_t computed = crc_in.crc();
                    uint32_t stored = 0;
                    raw_in >> stored;
                    if (stored != computed)
                        throw std::runtime_error(fmt::format(
                            "the map data does not match its checksum (CRC-32 {:08x} stored, {:08x} of the data "
                            "read): damaged after it was written",
                            stored, computed));
                }

                stage = "consistency check";
                PanopticMap m(o);
                m.restore(keys, std::move(voxels), std::move(surfaces), std::move(recs), std::move(irecs), next_id);
                m.restorePairEvidence(evidence);
                m.restoreSpills(spills);
                m.restoreInstanceFrames(instance_frames);
                map_ = std::move(m);
                insertionOptions = io;  // the pairer's options
                renderOptions = ro;
                genericMapParams = gp;
                pairer_.clear();
                stats_ = {};
            }
            catch (const NotAcceptedContent& e)
            {
                throw std::runtime_error(fmt::format("PanopticNDTMap: {}", e.what()));
            }
            catch (const std::exception& e)
            {
                throw std::runtime_error(fmt::format(
                    "PanopticNDTMap: archive is truncated or corrupt (while reading {}): {}", stage, e.what()));
            }
        }
        break;
        default:
            MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
    }
}

}  // namespace pndt
