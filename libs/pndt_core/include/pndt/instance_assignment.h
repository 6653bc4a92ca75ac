// Which map instance each predicted instance of a frame takes (paper step 4),
// free of images and maps so the rule can be checked by hand.
#pragma once

#include <pndt/instance_rules.h>

#include <cstdint>
#include <vector>

namespace pndt
{
/// The outcome for one predicted instance: a map instance (index into the
/// frame's map instances) or one of these.
constexpr int32_t kAssignNew = -1;        ///< a new, globally unique id
constexpr int32_t kAssignAmbiguous = -2;  ///< instance 0, no instance update

/// IoUs of the frame: iou[g * predictions + p] for map instance g and predicted
/// instance p; class_of[p] is p's semantic class and map_class[g] the thing class
/// of map instance g (0 = unknown; both may be null).
struct AssignmentInput
{
    const double* iou = nullptr;
    const uint16_t* class_of = nullptr;
    const uint16_t* map_class = nullptr;
    size_t map_instances = 0;
    size_t predictions = 0;
    double theta_m = 0.2;
    double theta_n = 0.1;
};

/// Paper rule: p takes its best map instance if J > theta_m, a new id if the best
/// J <= theta_n, else nothing; several predictions may take one map instance (a
/// split prediction keeps mapping onto its one object). One addition: map
/// instances of another thing class do not take part in p's match. Without this,
/// one early merged prediction (a chair with the rug it stands on) ties both
/// objects to one map instance for good (every later prediction of the rug
/// overlaps the merged instance enough to take it), and a bookshelf whose first
/// views only matched the vase in it stays ambiguous. A class confusion costs a
/// short-lived extra id instead, which loses to the right one in the voxels.
inline void assignPredictions(const AssignmentInput& in, std::vector<int32_t>& out)
{
    const size_t G = in.map_instances, P = in.predictions;
    out.assign(P, kAssignAmbiguous);
    const auto J = [&](size_t g, size_t p) { return in.iou[g * P + p]; };
    for (size_t p = 0; p < P; ++p)
    {
        const uint16_t pc = in.class_of ? in.class_of[p] : 0;
        double best = 0;
        int32_t best_g = -1;
        for (size_t g = 0; g < G; ++g)
        {
            const uint16_t gc = in.map_class ? in.map_class[g] : 0;
            if (J(g, p) > best && (pc == 0 || gc == 0 || gc == pc))
            {
                best = J(g, p);
                best_g = int32_t(g);
            }
        }
        switch (classifyMatch(best, in.theta_m, in.theta_n))
        {
            case MatchKind::Matched: out[p] = best_g; break;
            case MatchKind::New: out[p] = kAssignNew; break;
            case MatchKind::Ambiguous: break;
        }
    }
}

}  // namespace pndt
