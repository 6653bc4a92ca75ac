// .ini options of PanopticNDTMap and its CMultiMetricMap map definition.
#include <fmt/format.h>
#include <pndt/mrpt/PanopticNDTMap.h>
#include <pndt/mrpt/config_section.h>

#include <algorithm>
#include <cctype>
#include <sstream>
#include <vector>

namespace pndt
{
namespace
{
std::vector<std::string> splitList(const std::string& s)
{
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
    {
        const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
        if (b != std::string::npos) out.push_back(item.substr(b, e - b + 1));
    }
    return out;
}

ClassSet readClassSet(ConfigSection& s)
{
    std::string set_name = "nyuv2_40", names, stuff;
    s.read("class_set", set_name);
    s.read("class_names", names);
    s.read("stuff_classes", stuff);
    if (names.empty())
    {
        if (set_name != "nyuv2_40")
            throw std::invalid_argument(fmt::format(
                "config section '{}', key 'class_set': unknown class set '{}' (known: nyuv2_40; or give class_names)",
                s.name(), set_name));
        return ClassSet::nyuv2_40();
    }
    const auto list = splitList(names);
    const auto stuff_list = splitList(stuff.empty() ? "void" : stuff);
    // Class 0 is read as "no prediction" wherever labels are: a set whose class 0 is a real
    // class ("road") lost that class without a word.
    if (list.empty() || list[0] != "void")
        throw std::invalid_argument(fmt::format("config section '{}', key 'class_names': class 0 must be 'void' (no "
                                                "prediction), not '{}'",
                                                s.name(), list.empty() ? std::string() : list[0]));
    std::vector<ClassSet::Class> classes;
    for (const auto& n : list)
        classes.push_back({n, std::find(stuff_list.begin(), stuff_list.end(), n) == stuff_list.end()});
    classes[0].is_thing = false;  // void is stuff whether stuff_classes lists it or not
    for (const auto& n : stuff_list)
        if (std::find(list.begin(), list.end(), n) == list.end())
            throw std::invalid_argument(
                fmt::format("config section '{}', key 'stuff_classes': '{}' is not in class_names", s.name(), n));
    try
    {
        return ClassSet(std::move(classes));
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(fmt::format("config section '{}', key 'class_names': {}", s.name(), e.what()));
    }
}

const char* rangeKindName(RangeKind k) { return k == RangeKind::Z ? "z" : "ray"; }
const char* rayModeName(RayMode m) { return m == RayMode::Merged ? "merged" : "per_pixel"; }
const char* missAccumulationName(MissAccumulation m)
{
    return m == MissAccumulation::Strongest ? "strongest" : "per_ray";
}
const char* instanceClassVoxelsName(InstanceClassVoxels m)
{
    return m == InstanceClassVoxels::PanopticThing ? "pthing" : "top_instance";
}

/// Reads an enum option given by name; throws naming section, key and the choices.
template <typename E>
void readChoice(ConfigSection& s, const std::string& section, const char* key, E& value, const char* (*name)(E),
                std::initializer_list<E> choices)
{
    std::string text = name(value);
    s.read(key, text);
    std::string known;
    for (E c : choices)
    {
        if (text == name(c))
        {
            value = c;
            return;
        }
        known += (known.empty() ? "" : ", ") + std::string(name(c));
    }
    throw std::invalid_argument(fmt::format("config section '{}', key '{}': '{}' is not one of {}", section, key, text, known));
}
}  // namespace

void loadMapOptions(const mrpt::config::CConfigFileBase& c, const std::string& section, MapOptions& o)
{
    ConfigSection s(c, section);
    s.read("voxel_size", o.voxel_size);
    s.read("max_range", o.max_range);
    readChoice(s, section, "max_range_along", o.max_range_along, rangeKindName, {RangeKind::Z, RangeKind::Ray});
    s.read("use_ndt", o.use_ndt);
    readChoice(s, section, "ray_mode", o.ray_mode, rayModeName, {RayMode::Merged, RayMode::PerPixel});
    readChoice(s, section, "miss_accumulation", o.miss_accumulation, missAccumulationName,
               {MissAccumulation::Strongest, MissAccumulation::PerRay});
    s.read("log_odds_hit", o.log_odds_hit);
    s.read("log_odds_miss", o.log_odds_miss);
    s.read("log_odds_min", o.log_odds_min);
    s.read("log_odds_max", o.log_odds_max);
    s.read("occupied_threshold", o.occupied_threshold);
    s.read("reset_freed_voxels", o.reset_freed_voxels);
    s.read("ndt_min_samples", o.ndt_min_samples);
    s.read("ndt_sample_cap", o.ndt_sample_cap);
    s.read("ndt_min_sigma_ratio", o.ndt_min_sigma_ratio);
    s.read("miss_min_likelihood", o.miss_min_likelihood);
    s.read("miss_likelihood_scale", o.miss_likelihood_scale);
    s.read("sensor_sigma_base", o.sensor_sigma_base);
    s.read("sensor_sigma_quadratic", o.sensor_sigma_quadratic);
    s.read("theta_l", o.theta_l);
    s.read("theta_z", o.theta_z);
    s.read("theta_st", o.theta_st);
    s.read("theta_b", o.theta_b);
    s.read("theta_m", o.theta_m);
    s.read("theta_n", o.theta_n);
    s.read("theta_o", o.theta_o);
    readChoice(s, section, "instance_class_voxels", o.instance_class_voxels, instanceClassVoxelsName,
               {InstanceClassVoxels::PanopticThing, InstanceClassVoxels::TopInstance});
    s.read("semantic_eviction", o.semantic_eviction);
    s.read("void_bin", o.void_bin);
    s.read("split_coverage", o.split_coverage);
    s.read("class_consistent_instances", o.class_consistent_instances);
    s.read("fragment_merge_frames", o.fragment_merge_frames);
    s.read("fragment_min_mask_pixels", o.fragment_min_mask_pixels);
    s.read("fragment_cover_share", o.fragment_cover_share);
    s.read("fragment_joint_factor", o.fragment_joint_factor);
    s.read("fragment_absorb_ratio", o.fragment_absorb_ratio);
    s.read("label_fill_distance", o.label_fill_distance);
    s.read("vtou_mahalanobis_sq", o.vtou_mahalanobis_sq);
    s.read("vtou_depth_tolerance", o.vtou_depth_tolerance);
    s.read("query_mahalanobis_sq", o.query_mahalanobis_sq);
    uint32_t threads = uint32_t(o.threads);
    s.read("threads", threads);
    o.threads = int(std::min<uint32_t>(threads, 1000));  // validate() names anything above 256
    if (s.has("class_set") || s.has("class_names") || s.has("stuff_classes")) o.classes = readClassSet(s);
    // TMapGenericParams, read by MRPT itself from the same section.
    for (const char* k : {"enableSaveAs3DObject", "enableObservationLikelihood", "enableObservationInsertion"})
        s.allow(k);
    s.rejectUnknownKeys();
    try
    {
        o.validate();
    }
    catch (const std::invalid_argument& e)
    {
        throw std::invalid_argument(fmt::format("config section '{}': {}", section, e.what()));
    }
}

void dumpMapOptions(const MapOptions& o, std::ostream& out)
{
    out << fmt::format(
        "voxel_size = {}\nmax_range = {}\nmax_range_along = {}\nuse_ndt = {}\nray_mode = {}\nmiss_accumulation = {}\nlog_odds_hit = {}\n"
        "log_odds_miss = {}\nlog_odds_min = {}\nlog_odds_max = {}\noccupied_threshold = {}\nreset_freed_voxels = {}\n"
        "ndt_min_samples = {}\nndt_sample_cap = {}\nndt_min_sigma_ratio = {}\nmiss_min_likelihood = {}\n"
        "miss_likelihood_scale = {}\nsensor_sigma_base = {}\nsensor_sigma_quadratic = {}\n",
        o.voxel_size, o.max_range, rangeKindName(o.max_range_along), o.use_ndt, rayModeName(o.ray_mode), missAccumulationName(o.miss_accumulation),
        o.log_odds_hit, o.log_odds_miss, o.log_odds_min, o.log_odds_max, o.occupied_threshold, o.reset_freed_voxels,
        o.ndt_min_samples, o.ndt_sample_cap, o.ndt_min_sigma_ratio, o.miss_min_likelihood, o.miss_likelihood_scale,
        o.sensor_sigma_base, o.sensor_sigma_quadratic);
    out << fmt::format(
        "theta_l = {}\ntheta_z = {}\ntheta_st = {}\ntheta_b = {}\ntheta_m = {}\ntheta_n = {}\ntheta_o = {}\n"
        "instance_class_voxels = {}\nsemantic_eviction = {}\nvoid_bin = {}\nsplit_coverage = {}\n"
        "class_consistent_instances = {}\nfragment_merge_frames = {}\nfragment_min_mask_pixels = {}\n"
        "fragment_cover_share = {}\nfragment_joint_factor = {}\nfragment_absorb_ratio = {}\n"
        "label_fill_distance = {}\nvtou_mahalanobis_sq = {}\nvtou_depth_tolerance = {}\n"
        "query_mahalanobis_sq = {}\nthreads = {}\nclasses = {}\n",
        o.theta_l, o.theta_z, o.theta_st, o.theta_b, o.theta_m, o.theta_n, o.theta_o,
        instanceClassVoxelsName(o.instance_class_voxels), o.semantic_eviction, o.void_bin, o.split_coverage,
        o.class_consistent_instances, o.fragment_merge_frames, o.fragment_min_mask_pixels, o.fragment_cover_share,
        o.fragment_joint_factor, o.fragment_absorb_ratio, o.label_fill_distance, o.vtou_mahalanobis_sq,
        o.vtou_depth_tolerance, o.query_mahalanobis_sq, o.threads, o.classes.size());
}

void InsertionOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& section)
{
    ConfigSection s(c, section);
    s.read("label_pairing_tolerance", label_pairing_tolerance);
    s.read("semantic_suffix", semantic_suffix);
    s.read("instance_suffix", instance_suffix);
    uint64_t n = max_buffered_labels;
    s.read("max_buffered_labels", n);
    max_buffered_labels = size_t(n);
    s.read("refine_pose", refine_pose);
    s.read("refine_thing_weight", refine_thing_weight);
    s.read("refine_loss_scale", refine_loss_scale);
    s.rejectUnknownKeys();
    if (!(label_pairing_tolerance >= 0))
        throw std::invalid_argument(fmt::format("config section '{}', key 'label_pairing_tolerance' must be >= 0", section));
}

void InsertionOptions::dumpToTextStream(std::ostream& out) const
{
    out << fmt::format("label_pairing_tolerance = {}\nsemantic_suffix = {}\ninstance_suffix = {}\n"
                       "max_buffered_labels = {}\n",
                       label_pairing_tolerance, semantic_suffix, instance_suffix, max_buffered_labels);
    out << fmt::format("refine_pose = {}\nrefine_thing_weight = {}\nrefine_loss_scale = {}\n", refine_pose,
                       refine_thing_weight, refine_loss_scale);
}

void RenderOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& c, const std::string& section)
{
    ConfigSection s(c, section);
    std::string mode, sh;
    s.read("color_mode", mode);
    s.read("shape", sh);
    s.read("show_free", show_free);
    s.read("point_size", point_size);
    uint64_t n = max_ellipsoids;
    s.read("max_ellipsoids", n);
    max_ellipsoids = size_t(n);
    s.read("ellipsoid_quantile", ellipsoid_quantile);
    s.rejectUnknownKeys();
    if (mode == "semantic") color_mode = ColorMode::Semantic;
    else if (mode == "instance") color_mode = ColorMode::Instance;
    else if (mode == "panoptic") color_mode = ColorMode::Panoptic;
    else if (!mode.empty())
        throw std::invalid_argument(fmt::format(
            "config section '{}', key 'color_mode': '{}' is not semantic, instance or panoptic", section, mode));
    if (sh == "points") shape = VoxelShape::Points;
    else if (sh == "ellipsoids") shape = VoxelShape::Ellipsoids;
    else if (sh == "cubes") shape = VoxelShape::Cubes;
    else if (!sh.empty())
        throw std::invalid_argument(
            fmt::format("config section '{}', key 'shape': '{}' is not points, ellipsoids or cubes", section, sh));
}

void RenderOptions::dumpToTextStream(std::ostream& out) const
{
    static const char* modes[] = {"semantic", "instance", "panoptic"};
    static const char* shapes[] = {"points", "ellipsoids", "cubes"};
    out << fmt::format("color_mode = {}\nshape = {}\nshow_free = {}\npoint_size = {}\nmax_ellipsoids = {}\n"
                       "ellipsoid_quantile = {}\n",
                       modes[int(color_mode)], shapes[int(shape)], show_free, point_size, max_ellipsoids,
                       ellipsoid_quantile);
}

// ---- CMultiMetricMap map definition

PanopticNDTMap::TMapDefinition::TMapDefinition() = default;

namespace
{
/// A section named like this map's (<base>_NN_...) that no map reads: a typo there would
/// leave every option at its default without a word ("MAP_PanopticNDTMap_0_creationOpts").
void rejectMisnamedSections(const mrpt::config::CConfigFileBase& c, const std::string& prefix)
{
    const size_t cut = prefix.rfind('_');
    if (cut == std::string::npos) return;
    const std::string base = prefix.substr(0, cut + 1);  // "MAP_PanopticNDTMap_"
    std::vector<std::string> sections;
    c.getAllSections(sections);
    for (const std::string& s : sections)
    {
        if (s.size() < base.size() || !std::equal(base.begin(), base.end(), s.begin(), [](char a, char b) {
                return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
            }))
            continue;
        const std::string rest = s.substr(base.size());  // "00_creationOpts"
        const bool index = rest.size() > 3 && std::isdigit(static_cast<unsigned char>(rest[0])) &&
                           std::isdigit(static_cast<unsigned char>(rest[1])) && rest[2] == '_';
        std::string what = index ? rest.substr(3) : "";
        std::transform(what.begin(), what.end(), what.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
        if (what == "creationopts" || what == "insertopts" || what == "renderopts") continue;  // MRPT: any case
        throw std::invalid_argument(fmt::format(
            "config section '{}' is not read by PanopticNDTMap (its sections: '{}_creationOpts', '{}_insertOpts', "
            "'{}_renderOpts'{})",
            s, prefix, prefix, prefix,
            what == "likelihoodopts" ? "; likelihood options are set in code: navigationOptions.likelihood" : ""));
    }
}
}  // namespace

void PanopticNDTMap::TMapDefinition::loadFromConfigFile_map_specific(const mrpt::config::CConfigFileBase& c,
                                                                     const std::string& prefix)
{
    rejectMisnamedSections(c, prefix);
    // Sections: <prefix>_creationOpts (all map options), _insertOpts (pairing), _renderOpts.
    loadMapOptions(c, prefix + "_creationOpts", map_options);
    insertionOpts.loadFromConfigFile(c, prefix + "_insertOpts");
    renderOpts.loadFromConfigFile(c, prefix + "_renderOpts");
}

void PanopticNDTMap::TMapDefinition::dumpToTextStream_map_specific(std::ostream& out) const
{
    dumpMapOptions(map_options, out);
    insertionOpts.dumpToTextStream(out);
    renderOpts.dumpToTextStream(out);
}

mrpt::maps::CMetricMap* PanopticNDTMap::internal_CreateFromMapDefinition(const mrpt::maps::TMetricMapInitializer& def)
{
    const auto& d = dynamic_cast<const PanopticNDTMap::TMapDefinition&>(def);
    auto* m = new PanopticNDTMap(d.map_options);
    m->insertionOptions = d.insertionOpts;
    m->renderOptions = d.renderOpts;
    return m;
}

}  // namespace pndt
