// .npy / .npz readers (EMSANet predictions) and the id + score decoding.
#include "io_test_util.h"

#include <cstring>

#include <pndt/io/npz.h>

namespace pndt::io::test
{
namespace
{
/// 2x3 prediction: class/instance id + score.
const std::vector<float> kValues = {0.0f, 1.5f, 3.999f, 40.25f, 7.0f, 12.125f};

std::string npy123() { return makeNpy("<f4", "(1, 2, 3)", floatBytes(kValues)); }

void expectValues(const Image<float>& img)
{
    ASSERT_EQ(img.width, 3);
    ASSERT_EQ(img.height, 2);
    for (size_t i = 0; i < kValues.size(); ++i) EXPECT_EQ(img.data[i], kValues[i]);
    EXPECT_EQ(img.at(1, 0), 40.25f);  // row-major (C order)
}
}  // namespace

using Npz = TempDirTest;

TEST_F(Npz, StoredAndDeflatedMembers)
{
    const std::string stored = write("stored.npz", makeZip({{"arr_0.npy", npy123()}}));
    expectValues(readNpzImage(stored));

    ZipMember m{"arr_0.npy", makeNpy("<f4", "(2, 3)", floatBytes(kValues))};
    m.deflate = true;
    const std::string deflated = write("deflated.npz", makeZip({m}));
    expectValues(readNpzImage(deflated));
    EXPECT_EQ(listNpzArrays(deflated), std::vector<std::string>{"arr_0"});
}

TEST_F(Npz, Zip64ExtraFieldsAsWrittenByNumpy)
{
    ZipMember m{"arr_0.npy", npy123()};
    m.deflate = true;
    m.zip64_local = true;  // NumPy's savez uses zipfile.open(..., force_zip64=True)
    expectValues(readNpzImage(write("np.npz", makeZip({m}))));
    m.zip64_central = true;
    expectValues(readNpzImage(write("np64.npz", makeZip({m}))));
}

TEST_F(Npz, NamedMembersAndStacks)
{
    const std::string raw = floatBytes({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    const std::string p = write("multi.npz", makeZip({{"sem.npy", makeNpy("<f4", "(3, 2, 2)", raw)},
                                                    {"arr_0.npy", npy123()}}));
    const auto stack = readNpzImageStack(p, "sem");
    ASSERT_EQ(stack.size(), 3u);
    EXPECT_EQ(stack[2].at(1, 1), 12.0f);
    EXPECT_EQ(stack[1].at(0, 0), 5.0f);
    EXPECT_INPUT_ERROR(readNpzImage(p, "sem"), "multi.npz", "(3, 2, 2)", "expected (H, W) or (1, H, W)");
    EXPECT_INPUT_ERROR(readNpzImage(p, "nope"), "multi.npz", "no array 'nope'", "sem.npy");
    const NpyArray a = readNpzArray(p, "sem");
    EXPECT_EQ(a.shape, (std::vector<size_t>{3, 2, 2}));
    EXPECT_EQ(readNpyFile(write("x.npy", npy123())).shape, (std::vector<size_t>{1, 2, 3}));
}

TEST_F(Npz, DecodeIdAndScore)
{
    Image<float> packed(3, 2);
    packed.data = kValues;
    const IdScoreImages d = decodeIdScore(packed, "pred");
    EXPECT_EQ(d.ids.at(0, 0), 0);
    EXPECT_EQ(d.ids.at(0, 1), 1);
    EXPECT_FLOAT_EQ(d.scores.at(0, 1), 0.5f);
    EXPECT_EQ(d.ids.at(0, 2), 3);
    EXPECT_NEAR(d.scores.at(0, 2), 0.999f, 1e-6);
    EXPECT_EQ(d.ids.at(1, 0), 40);
    EXPECT_FLOAT_EQ(d.scores.at(1, 0), 0.25f);
    EXPECT_EQ(d.ids.at(1, 2), 12);
    EXPECT_FLOAT_EQ(d.scores.at(1, 2), 0.125f);
    // The documented safe range: ids < 16384 keep score 0.999 below id + 1.
    Image<float> big(1, 1, 16383.0f + 0.999f);
    EXPECT_EQ(decodeIdScore(big).ids.at(0, 0), 16383);

    Image<float> bad(2, 1, 1.0f);
    bad.at(0, 1) = -0.5f;
    EXPECT_INPUT_ERROR(decodeIdScore(bad, "frame_7.npz"), "frame_7.npz", "row 0, col 1");
    bad.at(0, 1) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_INPUT_ERROR(decodeIdScore(bad, "frame_7.npz"), "frame_7.npz");
}

TEST_F(Npz, MalformedArchivesNameTheFile)
{
    ZipMember m{"arr_0.npy", npy123()};
    m.deflate = true;
    const std::string zip = makeZip({m});
    EXPECT_INPUT_ERROR(readNpzImage(write("half.npz", zip.substr(0, zip.size() / 2))), "half.npz", "malformed zip");
    // Cut inside the deflate stream but keep a consistent directory: inflate must fail, not crash.
    EXPECT_INPUT_ERROR(readNpzImage(write("short.npz", zip.substr(0, zip.size() - 3))), "short.npz", "malformed zip");
    EXPECT_INPUT_ERROR(readNpzImage(write("text.npz", "just some text, definitely not a zip archive\n")), "text.npz", "not a zip");
    EXPECT_INPUT_ERROR(readNpzImage(write("tiny.npz", "PK")), "tiny.npz", "too short");
    EXPECT_INPUT_ERROR(readNpzImage(dir() + "/absent.npz"), "absent.npz", "file not found");

    // Flip one payload byte of a stored member: CRC check.
    std::string corrupt = makeZip({{"arr_0.npy", npy123()}});
    corrupt[30 + 9 + 130] ^= 0x5A;  // inside the float data (header is 128 bytes)
    EXPECT_INPUT_ERROR(readNpzImage(write("crc.npz", corrupt)), "crc.npz", "CRC");

    ZipMember bz{"arr_0.npy", npy123()};
    bz.method_override = 12;
    EXPECT_INPUT_ERROR(readNpzImage(write("bz.npz", makeZip({bz}))), "bz.npz", "compression method 12");
}

// Issue #23, found by fuzz_npz: a deflated member whose directory claims 2 GiB
// (2130706433 bytes) from a few hundred compressed bytes was allocated before inflating.
TEST_F(Npz, AnUncompressedSizeBeyondDeflatesRatioIsRefusedBeforeAllocating)
{
    ZipMember m{"arr_0.npy", npy123()};
    m.deflate = true;
    m.zip64_central = true;  // sizes as 64-bit fields in the central directory's extra field
    std::string zip = makeZip({m});
    const size_t central = zip.find("PK\x01\x02");
    ASSERT_NE(central, std::string::npos);
    std::string size_field(8, '\0');
    const uint64_t real = m.data.size(), claim = 2130706433;
    std::memcpy(size_field.data(), &real, 8);
    const size_t at = zip.find(size_field, central);
    ASSERT_NE(at, std::string::npos);
    std::memcpy(&zip[at], &claim, 8);
    EXPECT_INPUT_ERROR(readNpzImage(write("claims2g.npz", zip)), "claims2g.npz", "claims 2130706433 bytes",
                       "deflate expands at most 1032:1");
}

TEST_F(Npz, MalformedNpyNameTheFileAndProblem)
{
    const std::string f8 = floatBytes({1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
    EXPECT_INPUT_ERROR(readNpzImage(write("f8.npz", makeZip({{"arr_0.npy", makeNpy("<f8", "(2, 3)", f8)}}))),
                       "f8.npz", "dtype '<f8'", "expected '<f4'");
    EXPECT_INPUT_ERROR(readNpzImage(write("be.npz", makeZip({{"arr_0.npy", makeNpy(">f4", "(2, 3)", floatBytes(kValues))}}))),
                       "be.npz", "dtype '>f4'");
    EXPECT_INPUT_ERROR(readNpzImage(write("u2.npz", makeZip({{"arr_0.npy", makeNpy("<u2", "(2, 3)", std::string(12, '\0'))}}))),
                       "u2.npz", "dtype '<u2'");
    EXPECT_INPUT_ERROR(readNpzImage(write("fo.npz", makeZip({{"arr_0.npy", makeNpy("<f4", "(2, 3)", floatBytes(kValues), true)}}))),
                       "fo.npz", "Fortran order");
    EXPECT_INPUT_ERROR(readNpzImage(write("short.npz", makeZip({{"arr_0.npy", makeNpy("<f4", "(2, 4)", floatBytes(kValues))}}))),
                       "short.npz", "data truncated");
    EXPECT_INPUT_ERROR(readNpzImage(write("magic.npz", makeZip({{"arr_0.npy", "NOTNUMPY........"}}))),
                       "magic.npz", "arr_0.npy", "magic");
    EXPECT_INPUT_ERROR(readNpzImage(write("shape.npz", makeZip({{"arr_0.npy", makeNpy("<f4", "(2, x)", floatBytes(kValues))}}))),
                       "shape.npz", "shape");
    EXPECT_INPUT_ERROR(readNpzImage(write("one.npz", makeZip({{"arr_0.npy", makeNpy("<f4", "(6,)", floatBytes(kValues))}}))),
                       "one.npz", "(6,)");
}

}  // namespace pndt::io::test
