// Every JSON reader. First byte selects: 0 Open3D intrinsics, 1 nicr intrinsics,
// 2 nicr extrinsics (pose), 3 segmentation model description; the rest is the file.
#include <pndt/io/intrinsics.h>
#include <pndt/io/poses.h>
#include <pndt/seg/model_description.h>

#include "fuzz_util.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const uint8_t sel = pndt_fuzz::takeSelector(data, size) % 4;
    const std::string path = pndt_fuzz::writeInput(data, size, ".json");
    try
    {
        switch (sel)
        {
            case 0: (void)pndt::io::readOpen3dIntrinsicsJson(path); break;
            case 1:
            {
                const auto k = pndt::io::readNicrIntrinsicsJson(path);
                (void)k.toPixels(640, 480);
                break;
            }
            case 2: (void)pndt::io::readNicrPoses(path); break;
            default: (void)pndt::seg::loadModelDescription(path); break;
        }
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
