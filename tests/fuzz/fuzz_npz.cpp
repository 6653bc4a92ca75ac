// .npz (zip of .npy members, stored or deflated, ZIP64) as EMSANet writes them.
#include <pndt/io/npz.h>

#include "fuzz_util.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string path = pndt_fuzz::writeInput(data, size, ".npz");
    try
    {
        for (const auto& name : pndt::io::listNpzArrays(path))
        {
            try
            {
                const auto stack = pndt::io::readNpzImageStack(path, name);
                for (const auto& img : stack) (void)pndt::io::decodeIdScore(img, path);
            }
            catch (const std::exception&)
            {
            }
        }
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
