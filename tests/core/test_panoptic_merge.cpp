// The 2D panoptic merge of Eq. 1, and the class palette.
#include <gtest/gtest.h>
#include <pndt/panoptic_merge.h>

using namespace pndt;

TEST(PanopticMerge, ThingPixelsTakeTheMajorityClassOfTheirInstance)
{
    const ClassSet cs = ClassSet::nyuv2_40();
    // 1 x 5: instance 3 covers 4 pixels: chair, chair, sofa, wall(stuff); pixel 4 is floor.
    Image<uint16_t> sem(5, 1);
    sem.data = {5, 5, 6, 1, 2};
    Image<float> ss(5, 1);
    ss.data = {0.9f, 0.8f, 0.5f, 0.7f, 0.6f};
    Image<uint32_t> inst(5, 1);
    inst.data = {3, 3, 3, 3, 0};
    Image<float> is(5, 1, 0.5f);
    Image<uint16_t> os;
    Image<uint32_t> oi;
    Image<float> op;
    panopticMerge(cs, sem, ss, inst, is, os, oi, op);
    EXPECT_EQ(os.data, (std::vector<uint16_t>{5, 5, 5, 1, 2}));
    EXPECT_EQ(oi.data, (std::vector<uint32_t>{3, 3, 3, 0, 0}));
    EXPECT_FLOAT_EQ(op.data[0], 0.45f);
    EXPECT_FLOAT_EQ(op.data[2], 0.25f);
    EXPECT_FLOAT_EQ(op.data[3], 0.f);
}

TEST(PanopticMerge, RejectsUnknownClassesAndSizeMismatch)
{
    const ClassSet cs = ClassSet::nyuv2_40();
    Image<uint16_t> sem(2, 1, 41);
    Image<float> ss(2, 1, 1.f);
    Image<uint32_t> inst(2, 1, 0);
    Image<float> is(2, 1, 1.f);
    Image<uint16_t> os;
    Image<uint32_t> oi;
    Image<float> op;
    EXPECT_THROW(panopticMerge(cs, sem, ss, inst, is, os, oi, op), InputError);
    sem = Image<uint16_t>(2, 1, 5);
    inst = Image<uint32_t>(3, 1, 0);
    EXPECT_THROW(panopticMerge(cs, sem, ss, inst, is, os, oi, op), InputError);
}

// Class 0 is read as void everywhere, and classes are found by name: a set that breaks either
// was taken (a class 0 "road" lost without a word; two "c5" counted as one class).
TEST(ClassSet, ClassZeroIsVoidAndNamesAreUnique)
{
    const auto message = [](std::vector<ClassSet::Class> c) -> std::string {
        try
        {
            ClassSet s(std::move(c));
            return "no error";
        }
        catch (const std::invalid_argument& e)
        {
            return e.what();
        }
    };
    EXPECT_EQ(message({{"void", false}, {"wall", false}, {"chair", true}}), "no error");
    EXPECT_EQ(message({{"road", false}, {"chair", true}}), "class 0 must be 'void' (no prediction, stuff), not 'road'");
    EXPECT_EQ(message({{"void", true}, {"chair", true}}),
              "class 0 must be 'void' (no prediction, stuff), not 'void' (a thing)");
    EXPECT_EQ(message({{"void", false}, {"c5", true}, {"chair", true}, {"c5", false}}),
              "class name 'c5' is given twice (classes 1 and 3)");
    EXPECT_EQ(message({}), "a class set holds 1 to 255 classes (class 0 = void), not 0");
    std::vector<ClassSet::Class> many{{"void", false}};
    for (int i = 1; i < 256; ++i) many.push_back({"c" + std::to_string(i), true});
    EXPECT_EQ(message(many), "a class set holds 1 to 255 classes (class 0 = void), not 256");
}

TEST(ClassSet, Nyuv2StuffAndPalette)
{
    const ClassSet cs = ClassSet::nyuv2_40();
    EXPECT_EQ(cs.size(), 41u);
    EXPECT_FALSE(cs.isThing(1));
    EXPECT_FALSE(cs.isThing(22));
    EXPECT_TRUE(cs.isThing(5));
    EXPECT_TRUE(cs.isThing(40));
    EXPECT_EQ(cs.name(5), "chair");
    EXPECT_EQ(cs.find("ceiling"), 22);
    const Rgb c5 = classColor(5), c22 = classColor(22), c40 = classColor(40);
    EXPECT_EQ((std::array<int, 3>{c5.r, c5.g, c5.b}), (std::array<int, 3>{128, 0, 128}));
    EXPECT_EQ((std::array<int, 3>{c22.r, c22.g, c22.b}), (std::array<int, 3>{0, 192, 128}));
    EXPECT_EQ((std::array<int, 3>{c40.r, c40.g, c40.b}), (std::array<int, 3>{64, 0, 64}));
}
