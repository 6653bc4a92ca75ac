// Depth / label / colour image readers (PNG, JPEG, PNM, PFM; other formats are refused unread).
// First byte selects: 0 depth (mm), 1 depth (TUM units), 2 label, 3 colour.
#include <pndt/io/images.h>

#include "fuzz_util.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const uint8_t sel = pndt_fuzz::takeSelector(data, size) % 4;
    const std::string path = pndt_fuzz::writeInput(data, size, ".png");
    try
    {
        switch (sel)
        {
            case 0: (void)pndt::io::readDepthImage(path); break;
            case 1: (void)pndt::io::readDepthImage(path, pndt::io::kDepthUnitsTum); break;
            case 2: (void)pndt::io::readLabelImage(path); break;
            default: (void)pndt::io::readColorImage(path); break;
        }
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
