#include <pndt/live/stamp_order.h>

#include <fmt/format.h>

#include <algorithm>

namespace pndt::live
{
double StampOrder::leastArrivalOffset() const
{
    return *std::min_element(offsets_.begin(), offsets_.begin() + std::min(offset_count_, offsets_.size()));
}

StampOrder::Verdict StampOrder::next(double t, double arrival)
{
    message_.clear();
    if (t <= last_t_)
    {
        if (!in_gap_)
        {
            in_gap_ = true;
            gap_since_ = arrival;
            first_back_t_ = t;
            gap_least_offset_ = arrival - t;
            message_ = fmt::format(
                "the camera's frame stamp went back (t={:.6f} s after t={:.6f} s): frames are dropped and counted "
                "until its stamps pass t={:.6f} s",
                t, last_t_, last_t_);
        }
        else if (arrival - gap_since_ >= gap_limit_)
        {
            message_ = fmt::format(
                "the camera's frame stamps went back {:.3f} s (t={:.6f} s after t={:.6f} s) and did not pass "
                "t={:.6f} s again within {:.1f} s (its clock reset?)",
                last_t_ - first_back_t_, first_back_t_, last_t_, last_t_, gap_limit_);
            return Verdict::clock_reset;
        }
        gap_least_offset_ = std::min(gap_least_offset_, arrival - t);
        return Verdict::drop;
    }
    if (in_gap_)
    {
        in_gap_ = false;
        // Frames before the gap arrived at least this long after their stamps. If every frame
        // since (the gap's and this one) arrived later than that by more than kResetLag, the
        // stamps run behind time: a reset clock. One late frame leaves the others on time.
        const double since = std::min(gap_least_offset_, arrival - t);
        const double lag = device_clock_ && offset_count_ > 0 ? since - leastArrivalOffset() : 0.0;
        if (lag > kResetLag)
        {
            message_ = fmt::format(
                "the camera's clock was reset: its frame stamps went back {:.3f} s (t={:.6f} s after t={:.6f} s) and "
                "pass t={:.6f} s again {:.3f} s behind the host clock, so every later frame would take the pose of "
                "an earlier moment; restart pndt-live with a localiser on the camera's new clock",
                last_t_ - first_back_t_, first_back_t_, last_t_, last_t_, lag);
            return Verdict::clock_reset;
        }
        message_ = fmt::format("the camera's frame stamps are in order again at t={:.6f} s", t);
        offset_count_ = 0;  // the offset may have moved within kResetLag: measured afresh
    }
    if (device_clock_ && offset_count_ >= offsets_.size())
    {
        const double ahead = leastArrivalOffset() - (arrival - t);
        if (ahead > kJumpAhead)
        {
            message_ = fmt::format(
                "the camera's clock jumped {:.3f} s ahead of the host clock (t={:.6f} s after t={:.6f} s), so every "
                "later frame would wait for, and take, the pose of a later moment; restart pndt-live with a "
                "localiser on the camera's new clock",
                ahead, t, last_t_);
            return Verdict::clock_reset;
        }
    }
    last_t_ = t;
    offsets_[offset_count_++ % offsets_.size()] = arrival - t;
    return Verdict::take;
}
}  // namespace pndt::live
