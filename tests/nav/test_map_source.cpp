// Where pndt-nav's map comes from: a file, the newest map of a folder, and a
// folder followed as pndt-map writes new short-term maps.
#include <gtest/gtest.h>
#include <pndt/nav/map_source.h>
#include <unistd.h>

#include <fstream>

#include "nav_test_scene.h"

namespace fs = std::filesystem;
using namespace pndt;
using namespace pndt::nav;

namespace
{
fs::path tempDir()
{
    const fs::path d = fs::temp_directory_path() / ("pndt_nav_source_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}
}  // namespace

TEST(MapSource, FileFolderAndANewerMapAppearing)
{
    const fs::path dir = tempDir();
    EXPECT_THROW(newestMapFile(dir), InputError);  // empty folder
    fs::copy_file(navtest::savedMapPath(), dir / "map_0000.pndt.gz");
    LoadedMap m = loadNavigationMap(dir);
    EXPECT_EQ(m.file.filename(), "map_0000.pndt.gz");
    EXPECT_EQ(m.map->core().voxels().size(), navtest::builtMap().core().voxels().size());
    EXPECT_FALSE(reloadIfNewer(dir, m));  // nothing new
    fs::copy_file(navtest::savedMapPath(), dir / "map_0001.pndt.gz");
    fs::last_write_time(dir / "map_0001.pndt.gz", m.stamp + std::chrono::seconds(5));
    EXPECT_TRUE(reloadIfNewer(dir, m));
    EXPECT_EQ(m.file.filename(), "map_0001.pndt.gz");
    EXPECT_FALSE(reloadIfNewer(dir, m));
    // A file source never changes.
    LoadedMap f = loadNavigationMap(dir / "map_0000.pndt.gz");
    EXPECT_FALSE(reloadIfNewer(dir / "map_0000.pndt.gz", f));
    // Foreign or missing files: errors naming them.
    std::ofstream(dir / "junk.pndt.gz") << "not a map";
    try
    {
        loadNavigationMap(dir / "junk.pndt.gz");
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("junk.pndt.gz"), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadNavigationMap(dir / "none.pndt.gz"), InputError);
    fs::remove_all(dir);
}
