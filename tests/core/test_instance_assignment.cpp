// Which map instance each predicted instance takes (paper step 4 plus the class
// rule, design-decisions.md "Instances keep one class"), by hand.
#include <gtest/gtest.h>
#include <pndt/instance_assignment.h>

using namespace pndt;

namespace
{
constexpr uint16_t kChair = 5, kRug = 20;

std::vector<int32_t> assign(const std::vector<double>& iou, size_t G, size_t P, const std::vector<uint16_t>& pred_class,
                            const std::vector<uint16_t>& map_class)
{
    AssignmentInput in;
    in.iou = iou.data();
    in.map_instances = G;
    in.predictions = P;
    in.class_of = pred_class.empty() ? nullptr : pred_class.data();
    in.map_class = map_class.empty() ? nullptr : map_class.data();
    std::vector<int32_t> out;
    assignPredictions(in, out);
    return out;
}
}  // namespace

TEST(InstanceAssignment, WithoutClassesItIsThePaperRule)
{
    // Map instances g0, g1; predictions p0, p1, p2 (iou[g * 3 + p]).
    // p0: best 0.5 on g0 -> g0. p1: best 0.4 on g0 -> g0 too (not exclusive).
    // p2: best 0.15 -> ambiguous; with nothing above 0.1 it would be new.
    const std::vector<double> iou = {0.5, 0.4, 0.15,  //
                                     0.1, 0.3, 0.05};
    EXPECT_EQ(assign(iou, 2, 3, {}, {}), (std::vector<int32_t>{0, 0, kAssignAmbiguous}));
    const std::vector<double> low = {0.1, 0.0};
    EXPECT_EQ(assign(low, 2, 1, {}, {}), (std::vector<int32_t>{kAssignNew}));
}

TEST(InstanceAssignment, AMapInstanceOfAnotherClassTakesNoPartInTheMatch)
{
    // g0 is a chair that an early merged prediction also spread over the rug; g1 is
    // a rug. p0 (chair) J 0.6 with g0. p1 (rug): J 0.45 with g0 but only 0.25 with
    // g1 -> the paper takes g0 and ties the rug to the chair; the class rule takes g1.
    const std::vector<double> iou = {0.6, 0.45,  //
                                     0.0, 0.25};
    EXPECT_EQ(assign(iou, 2, 2, {kChair, kRug}, {kChair, kRug}), (std::vector<int32_t>{0, 1}));
    EXPECT_EQ(assign(iou, 2, 2, {kChair, kRug}, {}), (std::vector<int32_t>{0, 0}));
    // The rug's own instance only at 0.15: ambiguous; at 0.05 (or none): new id.
    const std::vector<double> amb = {0.6, 0.45, 0.0, 0.15};
    EXPECT_EQ(assign(amb, 2, 2, {kChair, kRug}, {kChair, kRug}), (std::vector<int32_t>{0, kAssignAmbiguous}));
    const std::vector<double> none = {0.6, 0.45, 0.0, 0.05};
    EXPECT_EQ(assign(none, 2, 2, {kChair, kRug}, {kChair, kRug}), (std::vector<int32_t>{0, kAssignNew}));
    // A map instance of unknown class (0) and a prediction of unknown class match anything.
    EXPECT_EQ(assign(iou, 2, 2, {kChair, kRug}, {0, kRug}), (std::vector<int32_t>{0, 0}));
    EXPECT_EQ(assign(iou, 2, 2, {kChair, 0}, {kChair, kRug}), (std::vector<int32_t>{0, 0}));
}

TEST(InstanceRules, OwnThingClassIgnoresStuffAndPicksTheHeaviestThing)
{
    const ClassSet classes = ClassSet::nyuv2_40();
    LabelRecord r;
    r.semantic.add(1, 9.f);  // wall: stuff
    r.semantic.add(kRug, 2.f);
    r.semantic.add(kChair, 3.f);
    EXPECT_EQ(ownThingClass(r, classes), kChair);
    LabelRecord stuff;
    stuff.semantic.add(1, 9.f);
    EXPECT_EQ(ownThingClass(stuff, classes), 0);
}
