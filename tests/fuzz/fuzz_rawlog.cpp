// Rawlogs as pndt-map reads them: ObservationStream (either rawlog format, gzip or
// plain, with its guard against short reads and corrupt JPEG colour images), then
// every observation through the depth / label pairing that builds the map's frames.
#include <pndt/app/observation_stream.h>
#include <pndt/mrpt/observation_pairer.h>

#include "fuzz_util.h"

#include <exception>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::string path = pndt_fuzz::writeInput(data, size, ".rawlog");
    try
    {
        pndt::app::ObservationStream stream(path, pndt::app::UncheckedObjects::Refused);  // every byte checked
        pndt::ObservationPairer pairer;
        std::vector<pndt::PairedFrame> done;
        for (int i = 0; i < 64; ++i)
        {
            const auto obs = stream.next();
            if (!obs) break;
            try
            {
                pairer.push(*obs, mrpt::poses::CPose3D(), done);
            }
            catch (const std::exception&)
            {
            }
            done.clear();
        }
        pairer.flush(done);
        (void)stream.stopReason();
    }
    catch (const std::exception&)
    {
    }
    return 0;
}
