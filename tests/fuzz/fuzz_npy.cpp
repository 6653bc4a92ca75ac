// A single .npy (header dict + float32 data), as parsed inside every .npz member.
#include <pndt/io/npz.h>

#include <cstdint>
#include <exception>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    try
    {
        const auto a = pndt::io::parseNpyFloat32(std::string(reinterpret_cast<const char*>(data), size), "fuzz.npy");
        if (a.shape.size() == 2 || (a.shape.size() == 3 && a.shape[0] == 1)) (void)a.data.size();
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
