#include <fmt/format.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/instance_numbering.h>
#include <pndt/mrpt/map_files.h>
#include <pndt/mrpt/voxel_colors.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace pndt
{
void saveArchive(const mrpt::serialization::CSerializable& obj, const std::string& path)
{
    // Serialised and compressed in memory, then written with checked write()s: MRPT's gzip
    // stream ignores the result of gzclose(), so a full disk could leave a truncated archive
    // that would still be renamed into place (and listed in index.json).
    mrpt::io::CMemoryStream mem;
    {
        auto a = mrpt::serialization::archiveFrom(mem);
        a << obj;
    }
    // gzip (level 1, as MRPT's gzip stream writes) straight from the serialised bytes.
    z_stream z{};
    if (deflateInit2(&z, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        throw io::WriteError(fmt::format("cannot write '{}': gzip initialisation failed", path));
    const uint64_t n_in = mem.getTotalBytesCount();
    std::vector<uint8_t> gz(size_t(deflateBound(&z, uLong(n_in)) + 64));
    auto* in = static_cast<Bytef*>(mem.getRawBufferData());
    uint64_t in_left = n_in;
    z.next_out = gz.data();
    z.avail_out = uInt(std::min<size_t>(gz.size(), UINT32_MAX));
    int rc = Z_OK;
    while (rc == Z_OK)  // chunks of < 4 GiB (zlib counts in 32 bits)
    {
        if (z.avail_in == 0 && in_left > 0)
        {
            z.next_in = in + (n_in - in_left);
            z.avail_in = uInt(std::min<uint64_t>(in_left, 1u << 30));
            in_left -= z.avail_in;
        }
        if (z.avail_out == 0) break;
        rc = deflate(&z, in_left == 0 ? Z_FINISH : Z_NO_FLUSH);
    }
    gz.resize(size_t(z.next_out - gz.data()));
    deflateEnd(&z);
    if (rc != Z_STREAM_END) throw io::WriteError(fmt::format("cannot write '{}': gzip compression failed", path));
    io::writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(gz.data()), gz.size()));
}

PanopticNDTMap::Ptr loadMapArchive(const std::string& path)
{
    if (!std::filesystem::exists(path)) throw std::runtime_error(fmt::format("{}: no such file", path));
    // The whole file through zlib first: a stream read stops after the object and never
    // reaches the gzip trailer, so a file cut in its last bytes loaded as complete.
    std::string bytes;
    {
        gzFile gz = gzopen(path.c_str(), "rb");
        if (!gz) throw std::runtime_error(fmt::format("{}: cannot open", path));
        char buf[1 << 16];
        int got = 0;
        while ((got = gzread(gz, buf, sizeof buf)) > 0) bytes.append(buf, size_t(got));
        int code = 0;
        const std::string message = gzerror(gz, &code);
        gzclose(gz);
        if (got < 0 || (code != Z_OK && code != Z_STREAM_END))
            throw std::runtime_error(fmt::format("{}: not a readable map archive: the compressed data is cut or "
                                                 "corrupt ({})",
                                                 path, message));
    }
    mrpt::io::CMemoryStream f;
    f.assignMemoryNotOwn(bytes.data(), bytes.size());
    mrpt::serialization::CSerializable::Ptr obj;
    try
    {
        auto a = mrpt::serialization::archiveFrom(f);
        a >> obj;
    }
    catch (const std::exception& e)
    {
        throw std::runtime_error(fmt::format("{}: not a readable map archive: {}", path, e.what()));
    }
    auto map = std::dynamic_pointer_cast<PanopticNDTMap>(obj);
    if (!map)
        throw std::runtime_error(fmt::format("{}: holds a {}, not a pndt::PanopticNDTMap", path,
                                             obj ? obj->GetRuntimeClass()->className : "null object"));
    return map;
}

void writePly(const PanopticNDTMap& m, const std::string& path, ColorMode colors)
{
    const PanopticMap& map = m.core();
    map.finalize();
    const auto& store = map.voxels();
    const InstanceNumbering numbering = InstanceNumbering::of(map);
    std::vector<uint32_t> occupied;
    for (uint32_t i = 0; i < store.size(); ++i)
        if (map.isOccupied(store[i])) occupied.push_back(i);
    io::writeFileAtomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        if (!f) throw io::WriteError(fmt::format("cannot write '{}': cannot open '{}'", path, tmp));
        f << "ply\nformat binary_little_endian 1.0\ncomment PanopticNDT map, voxel "
          << map.options().voxel_size
          << " m\ncomment label = semantic << 16 | n, n = the instance's rank among the map's instance ids "
             "(1 = smallest; instance holds the id itself)\nelement vertex " << occupied.size()
          << "\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\n"
             "property ushort semantic\nproperty uint instance\nproperty uint label\n"
             "property float occupancy\nend_header\n";
        for (uint32_t i : occupied)
        {
            const Voxel& v = store[i];
            const Eigen::Vector3d p = map.pointOf(i);
            const float xyz[3] = {float(p.x()), float(p.y()), float(p.z())};
            const Rgb c = voxelColor(map, i, colors);
            const PanopticLabel pl = map.panopticLabel(i);
            const uint16_t sem = pl.semantic;
            const uint32_t inst = pl.instance;
            const uint32_t label = (uint32_t(sem) << 16) | numbering.dense(inst);
            const float prob = float(1.0 / (1.0 + std::exp(-double(v.occ))));
            f.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
            f.write(reinterpret_cast<const char*>(&c.r), 1);
            f.write(reinterpret_cast<const char*>(&c.g), 1);
            f.write(reinterpret_cast<const char*>(&c.b), 1);
            f.write(reinterpret_cast<const char*>(&sem), sizeof(sem));
            f.write(reinterpret_cast<const char*>(&inst), sizeof(inst));
            f.write(reinterpret_cast<const char*>(&label), sizeof(label));
            f.write(reinterpret_cast<const char*>(&prob), sizeof(prob));
        }
        io::closeWrittenStream(f, path);
    });
}

void PanopticNDTMap::saveMetricMapRepresentationToFile(const std::string& prefix) const
{
    writePly(*this, prefix + ".ply", renderOptions.color_mode);
}

}  // namespace pndt
