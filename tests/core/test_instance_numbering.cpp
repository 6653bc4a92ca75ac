// InstanceNumbering: the dense 1..N numbering of a map's instance ids for 16-bit fields.
#include <gtest/gtest.h>
#include <pndt/instance_numbering.h>

using namespace pndt;

TEST(InstanceNumbering, RanksIdsInAscendingOrderAndInverts)
{
    // Ids of a map after two hand-overs (blocks of 65536), given unsorted with a repeat and 0.
    const InstanceNumbering n({131075, 65537, 0, 131073, 65537});
    EXPECT_EQ(n.size(), 3u);
    EXPECT_EQ(n.dense(0), 0u);
    EXPECT_EQ(n.dense(65537), 1u);
    EXPECT_EQ(n.dense(131073), 2u);
    EXPECT_EQ(n.dense(131075), 3u);
    for (uint32_t k = 0; k <= 3; ++k) EXPECT_EQ(n.dense(n.mapId(k)), k);
    EXPECT_FALSE(n.isIdentity());
    EXPECT_TRUE(InstanceNumbering({3, 1, 2}).isIdentity());
    EXPECT_TRUE(InstanceNumbering().isIdentity());
}

TEST(InstanceNumbering, UnknownIdsAndTooManyInstancesAreRefusedWithTheNumbers)
{
    const InstanceNumbering n({5, 9});
    try
    {
        n.dense(7);
        FAIL() << "id 7 is not in the map";
    }
    catch (const std::out_of_range& e)
    {
        EXPECT_NE(std::string(e.what()).find("instance id 7 is not one of the map's 2 instances"), std::string::npos);
    }
    EXPECT_THROW(n.mapId(3), std::out_of_range);
    std::vector<uint32_t> many(65536);
    for (uint32_t i = 0; i < many.size(); ++i) many[i] = 100000 + i;
    try
    {
        InstanceNumbering too_many(many);
        FAIL() << "65536 instances do not fit 16 bits";
    }
    catch (const std::out_of_range& e)
    {
        EXPECT_NE(std::string(e.what()).find("65536 instances"), std::string::npos);
    }
    many.pop_back();
    EXPECT_EQ(InstanceNumbering(many).dense(100000 + 65534), 65535u);
}
