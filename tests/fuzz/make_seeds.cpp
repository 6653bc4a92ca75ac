// Writes the binary seeds that cannot be small text fixtures: a tiny labelled map as
// an uncompressed MRPT archive and a tiny uncompressed rawlog (depth + colour JPEG +
// both label images + a robot pose), with the observations of the plugin tests.
// Usage: fuzz_make_seeds CORPUS_DIR   (writes map_archive/seed_map.pndt, rawlog/seed.rawlog)
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/serialization/CArchive.h>
#include <pndt/mrpt/PanopticNDTMap.h>

#include "../mrpt/observation_fixtures.h"

#include <filesystem>
#include <iostream>

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::cerr << "usage: fuzz_make_seeds CORPUS_DIR\n";
        return 2;
    }
    const std::filesystem::path dir = argv[1];
    std::filesystem::create_directories(dir / "map_archive");
    std::filesystem::create_directories(dir / "rawlog");
    pndt::MapOptions options;
    options.voxel_size = 0.6;  // a handful of voxels: a small seed
    auto m = pndt::PanopticNDTMap::Create(options);
    mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);  // colour images as JPEG (the guard's input)
    {
        mrpt::io::CFileOutputStream f((dir / "rawlog" / "seed.rawlog").string());
        auto a = mrpt::serialization::archiveFrom(f);
        for (int i = 0; i < 2; ++i)
        {
            const mrpt::poses::CPose3D robot(0.0, 0.05 * i, 0.0, 0.02 * i, 0.0, 0.0);
            auto scan = fixtures::wallScan(i);
            if (i == 1)
            {
                scan->hasIntensityImage = true;
                scan->intensityImage.resize(fixtures::kW, fixtures::kH, mrpt::img::CH_RGB);
                scan->intensityImage.filledRectangle(0, 0, fixtures::kW - 1, fixtures::kH - 1,
                                                     mrpt::img::TColor(200, 80, 40));
            }
            auto pose = mrpt::obs::CObservationRobotPose::Create();
            pose->sensorLabel = "GT_POSE";
            pose->timestamp = scan->timestamp;
            pose->pose.mean = robot;
            a << *pose << *scan << *fixtures::semanticImage(i) << *fixtures::instanceImage(i);
            m->insertObservation(*scan, robot);
            m->insertObservation(*fixtures::semanticImage(i), robot);
            m->insertObservation(*fixtures::instanceImage(i), robot);
        }
    }
    m->flushPending();
    mrpt::io::CFileOutputStream f((dir / "map_archive" / "seed_map.pndt").string());
    auto a = mrpt::serialization::archiveFrom(f);
    a << *m;
    std::cout << "seeds written to " << dir << " (" << m->core().voxels().size() << " voxels)\n";
    return 0;
}
