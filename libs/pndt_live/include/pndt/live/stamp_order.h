#pragma once
// The order of a camera's frame stamps, checked at capture (doc/hardening.md, "A camera clock
// that goes back"). Poses are looked up, maps handed over and the recording cut by frame time,
// so a frame not after the one before is dropped. Stamps that pass the last one again end the
// gap - unless, with the camera's own clock, they now lag the host clock: then the device
// clock was reset and every later frame would take the pose of an earlier moment. A device
// clock that jumps ahead of the host clock is lost the same way: its frames would wait for
// poses of later moments, and take them.
#include <array>
#include <cstddef>
#include <string>

namespace pndt::live
{
class StampOrder
{
   public:
    enum class Verdict
    {
        take,         ///< after the frame before: map it
        drop,         ///< not after the frame before: dropped and counted
        clock_reset,  ///< the camera is lost (its clock reset or jumped ahead): message() says why
    };

    /// A lag of the device clock behind the host clock larger than this, seen in every frame
    /// from the stamp going back to it passing the last one again, is a reset (a frame
    /// delivered late lags by its delay, but the frames after it do not lag at all).
    static constexpr double kResetLag = 0.25;
    /// A frame stamped this much further ahead of its arrival than the least-delayed of the
    /// last 32 in-order frames was stamped by a clock that jumped forward (a frame cannot
    /// arrive before it is taken; delivery delays only add). Judged once those 32 are seen.
    static constexpr double kJumpAhead = 0.25;

    /// device_clock: stamps come from the camera (a lag against arrival means a reset);
    /// with host stamps only the order is checked. gap_limit: seconds the stamps may stay
    /// behind before the camera counts as lost.
    StampOrder(bool device_clock, double gap_limit) : device_clock_(device_clock), gap_limit_(gap_limit) {}

    /// Frame stamp t (seconds) that arrived at host time `arrival` (seconds of a steady clock).
    Verdict next(double t, double arrival);

    /// What to say about the frame just judged: for take and drop the line to print when a
    /// gap ends or starts (empty if none); for clock_reset why the camera is lost.
    const std::string& message() const { return message_; }

   private:
    double leastArrivalOffset() const;

    bool device_clock_;
    double gap_limit_;
    double last_t_ = -1e300;     // stamps may be < 0 (--stamp-offset)
    bool in_gap_ = false;
    double gap_since_ = 0, first_back_t_ = 0;
    double gap_least_offset_ = 0;  // least arrival minus stamp of the gap's frames
    // Arrival minus stamp of the latest in-order frames: the least is the device clock's
    // offset to the host clock with the least delivery delay.
    std::array<double, 32> offsets_{};
    size_t offset_count_ = 0;
    std::string message_;
};
}  // namespace pndt::live
