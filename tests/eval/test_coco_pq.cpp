// PQ on real COCO panoptic ground truth (cocodataset/panopticapi sample_data, see
// shared/data/coco-panoptic-sample/SOURCE.md): the GT against itself, then a prediction
// perturbed by hand whose PQ is worked out in the comments.
//
// Conversion to the (class, instance) labelling PanopticQuality takes: class = COCO
// category id (a 201-entry label space; isthing from the JSON), instance = 1-based index of
// the segment in its image's segments_info for things, 0 for stuff. TF-models / nicr PQ
// has no "crowd" notion, so crowd GT segments become void; a crowd-region prediction then
// lies entirely on void and is ignored, as in panopticapi.
#include <gtest/gtest.h>
#include <pndt/eval/panoptic_quality.h>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>
#include <map>

using namespace pndt::eval;
namespace fs = std::filesystem;
using nlohmann::json;

namespace
{
const fs::path kDir = fs::path(PNDT_SHARED_DATA_DIR) / "coco-panoptic-sample" / "sample_data";

struct Segment
{
    uint16_t category = 0;
    uint32_t instance = 0;
    bool crowd = false;
    uint64_t area = 0;  ///< from the JSON
};

struct CocoImage
{
    std::string file;
    int width = 0, height = 0;
    std::vector<uint32_t> segment_id;  ///< per pixel: R + 256 G + 256^2 B
    std::map<uint32_t, Segment> segments;
};

struct Coco
{
    Benchmark benchmark{"x", pndt::ClassSet({{"void", false}}), {}, {}};
    std::vector<CocoImage> images;
};

Coco loadCoco()
{
    std::ifstream in(kDir / "panoptic_examples.json");
    const json j = json::parse(in);
    // COCO's ids have gaps: placeholders with names of their own (a class set's names are unique).
    std::vector<pndt::ClassSet::Class> classes;
    for (int id = 0; id <= 200; ++id) classes.push_back({"unused " + std::to_string(id), false});
    classes[0] = {"void", false};
    std::vector<uint16_t> sem, ins;
    for (const json& c : j.at("categories"))
    {
        const int id = c.at("id");
        classes.at(size_t(id)) = {c.at("name").get<std::string>(), c.at("isthing").get<int>() == 1};
        sem.push_back(uint16_t(id));
        if (classes[size_t(id)].is_thing) ins.push_back(uint16_t(id));
    }
    Coco coco{Benchmark("coco", pndt::ClassSet(classes), sem, ins), {}};
    for (const json& a : j.at("annotations"))
    {
        CocoImage img;
        img.file = a.at("file_name").get<std::string>();
        uint32_t next = 1;
        for (const json& s : a.at("segments_info"))
        {
            Segment seg;
            seg.category = s.at("category_id").get<uint16_t>();
            seg.crowd = s.at("iscrowd").get<int>() == 1;
            seg.area = s.at("area").get<uint64_t>();
            seg.instance = coco.benchmark.isThing(seg.category) ? next++ : 0;
            img.segments[s.at("id").get<uint32_t>()] = seg;
        }
        const cv::Mat bgr = cv::imread((kDir / "panoptic_examples" / img.file).string(), cv::IMREAD_COLOR);
        if (bgr.empty()) throw std::runtime_error("cannot read " + img.file);
        img.width = bgr.cols;
        img.height = bgr.rows;
        for (int r = 0; r < bgr.rows; ++r)
            for (int c = 0; c < bgr.cols; ++c)
            {
                const cv::Vec3b p = bgr.at<cv::Vec3b>(r, c);  // B, G, R
                img.segment_id.push_back(uint32_t(p[2]) + 256u * p[1] + 65536u * p[0]);
            }
        coco.images.push_back(std::move(img));
    }
    return coco;
}

/// Per-pixel class and instance of a segment-id image; `gt` turns crowd segments into void.
void labels(const CocoImage& img, const std::vector<uint32_t>& segment_id, bool gt, std::vector<uint16_t>& sem,
            std::vector<uint32_t>& ins)
{
    sem.assign(segment_id.size(), 0);
    ins.assign(segment_id.size(), 0);
    for (size_t i = 0; i < segment_id.size(); ++i)
    {
        const auto it = img.segments.find(segment_id[i]);
        if (it == img.segments.end() || (gt && it->second.crowd)) continue;
        sem[i] = it->second.category;
        ins[i] = it->second.instance;
    }
}

bool haveData() { return fs::exists(kDir / "panoptic_examples.json"); }
}  // namespace

TEST(CocoPanopticSample, PixelAreasMatchTheJson)
{
    if (!haveData()) GTEST_SKIP() << "no shared data at " << kDir;
    const Coco coco = loadCoco();
    ASSERT_EQ(coco.images.size(), 2u);
    for (const CocoImage& img : coco.images)
    {
        std::map<uint32_t, uint64_t> count;
        for (uint32_t id : img.segment_id) ++count[id];
        for (const auto& [id, seg] : img.segments) EXPECT_EQ(count[id], seg.area) << img.file << " segment " << id;
    }
}

TEST(CocoPanopticSample, GroundTruthAgainstItselfIs100)
{
    if (!haveData()) GTEST_SKIP() << "no shared data at " << kDir;
    const Coco coco = loadCoco();
    PanopticQuality pq(coco.benchmark);
    std::vector<uint16_t> gs, ps;
    std::vector<uint32_t> gi, pi;
    for (const CocoImage& img : coco.images)
    {
        labels(img, img.segment_id, true, gs, gi);
        labels(img, img.segment_id, false, ps, pi);  // crowd regions stay in the prediction
        pq.add(gs.data(), gi.data(), ps.data(), pi.data(), gs.size());
    }
    const PqResult r = pq.result();
    // panopticapi on the same data: PQ = SQ = RQ = 100 for All (N=8), Things (4), Stuff (4).
    EXPECT_DOUBLE_EQ(r.all.pq, 1.0);
    EXPECT_DOUBLE_EQ(r.all.sq, 1.0);
    EXPECT_DOUBLE_EQ(r.all.rq, 1.0);
    EXPECT_EQ(r.all.n, 8u);
    EXPECT_DOUBLE_EQ(r.things.pq, 1.0);
    EXPECT_EQ(r.things.n, 4u);
    EXPECT_DOUBLE_EQ(r.stuff.pq, 1.0);
    EXPECT_EQ(r.stuff.n, 4u);
    EXPECT_EQ(r.all_any.n, 8u);  // no FP anywhere: the panopticapi set is the same
    for (const PqClass& c : r.classes) EXPECT_EQ(c.fp + c.fn, 0u) << c.id;
}

TEST(CocoPanopticSample, PerturbedPredictionByHand)
{
    if (!haveData()) GTEST_SKIP() << "no shared data at " << kDir;
    Coco coco = loadCoco();
    // Perturbations of the prediction (GT unchanged); areas from the JSON, checked above.
    // 000000142238:
    //   (a) person 4917453 (477 px) dropped to void           -> person: 1 FN.
    //   (b) sky 11829830 (8204 px) predicted as grass          -> sky: 1 FN; the grass
    //       prediction = grass (75100) + sky (8204): IoU 75100 / 83304, still a TP.
    // 000000439180:
    //   (c) horse 16762012 (573 px) merged into horse 16758454 (4363 px): the merged
    //       prediction has IoU 4363 / 4936 with 16758454 (TP), 16762012 is a FN.
    //   (d) truck 4587520 (1680 px) predicted as a new horse   -> truck: 1 FN, horse: 1 FP
    //       (the prediction lies on the truck, not on void).
    const uint32_t kPersonDropped = 4917453, kSky = 11829830, kGrass = 10025880;
    const uint32_t kHorseA = 16758454, kHorseB = 16762012, kTruck = 4587520, kFakeHorse = 1;  // id 1 is unused
    CocoImage& img1 = coco.images[0];
    CocoImage& img2 = coco.images[1];
    ASSERT_EQ(img1.file, "000000142238.png");
    ASSERT_EQ(img2.file, "000000439180.png");
    img2.segments[kFakeHorse] = {19, 999, false, 0};
    std::vector<uint32_t> pred1 = img1.segment_id, pred2 = img2.segment_id;
    for (uint32_t& s : pred1)
        if (s == kPersonDropped) s = 0;
        else if (s == kSky) s = kGrass;
    for (uint32_t& s : pred2)
        if (s == kHorseB) s = kHorseA;
        else if (s == kTruck) s = kFakeHorse;

    PanopticQuality pq(coco.benchmark);
    std::vector<uint16_t> gs, ps;
    std::vector<uint32_t> gi, pi;
    labels(img1, img1.segment_id, true, gs, gi);
    labels(img1, pred1, false, ps, pi);
    pq.add(gs.data(), gi.data(), ps.data(), pi.data(), gs.size());
    labels(img2, img2.segment_id, true, gs, gi);
    labels(img2, pred2, false, ps, pi);
    pq.add(gs.data(), gi.data(), ps.data(), pi.data(), gs.size());
    const PqResult r = pq.result();

    // Per class (TP / FN / FP; SQ; RQ = TP / (TP + FN/2 + FP/2)):
    //   person (1):   26 non-crowd GT, 25 / 1 / 0; SQ 1;                      RQ 25/25.5
    //   sports ball:  1 / 0 / 0; 1, 1
    //   truck (8):    1 / 1 / 0; SQ 1;                                        RQ 2/3
    //   horse (19):   11 non-crowd GT, 10 / 1 / 1; SQ (9 + 4363/4936) / 10;   RQ 10/11
    //   gravel, tree: PQ 1
    //   sky (187):    1 / 1 / 0; SQ 1;                                        RQ 2/3
    //   grass (193):  2 / 0 / 0; SQ (1 + 75100/83304) / 2;                    RQ 1
    const double a = 4363.0 / 4936, g = 75100.0 / 83304;
    EXPECT_EQ(r.find(1)->tp, 25u);
    EXPECT_EQ(r.find(1)->fn, 1u);
    EXPECT_EQ(r.find(19)->tp, 10u);
    EXPECT_EQ(r.find(19)->fn, 1u);
    EXPECT_EQ(r.find(19)->fp, 1u);
    EXPECT_NEAR(r.find(19)->sq, (9 + a) / 10, 1e-12);
    EXPECT_NEAR(r.find(193)->sq, (1 + g) / 2, 1e-12);
    EXPECT_EQ(r.find(187)->fn, 1u);
    EXPECT_EQ(r.find(8)->fn, 1u);

    const double pq_person = 25 / 25.5, pq_truck = 2.0 / 3, pq_horse = (9 + a) / 10 * (10.0 / 11);
    const double pq_sky = 2.0 / 3, pq_grass = (1 + g) / 2;
    // All (8 classes):    PQ 89.5378 %, SQ 99.2394 %, RQ 90.2852 %
    EXPECT_EQ(r.all.n, 8u);
    EXPECT_NEAR(r.all.pq, (pq_person + 1 + pq_truck + pq_horse + 1 + 1 + pq_sky + pq_grass) / 8, 1e-12);
    EXPECT_NEAR(r.all.sq, (1 + 1 + 1 + (9 + a) / 10 + 1 + 1 + 1 + (1 + g) / 2) / 8, 1e-12);
    EXPECT_NEAR(r.all.rq, (25 / 25.5 + 1 + 2.0 / 3 + 10.0 / 11 + 1 + 1 + 2.0 / 3 + 1) / 8, 1e-12);
    EXPECT_NEAR(100 * r.all.pq, 89.5378, 1e-4);
    EXPECT_NEAR(100 * r.all.sq, 99.2394, 1e-4);
    EXPECT_NEAR(100 * r.all.rq, 90.2852, 1e-4);
    // Things (person, sports ball, truck, horse): PQ 88.6399 %, SQ 99.7098 %, RQ 88.9037 %
    EXPECT_NEAR(r.things.pq, (pq_person + 1 + pq_truck + pq_horse) / 4, 1e-12);
    EXPECT_NEAR(100 * r.things.pq, 88.6399, 1e-4);
    EXPECT_NEAR(100 * r.things.sq, 99.7098, 1e-4);
    EXPECT_NEAR(100 * r.things.rq, 88.9037, 1e-4);
    // Stuff (gravel, tree, sky, grass): PQ 90.4356 %, SQ 98.7690 %, RQ 91.6667 %
    EXPECT_NEAR(r.stuff.pq, (1 + 1 + pq_sky + pq_grass) / 4, 1e-12);
    EXPECT_NEAR(100 * r.stuff.pq, 90.4356, 1e-4);
    EXPECT_NEAR(100 * r.stuff.sq, 98.7690, 1e-4);
    EXPECT_NEAR(100 * r.stuff.rq, 91.6667, 1e-4);
}
