#include <fmt/format.h>
#include <mrpt/gui/CDisplayWindow3D.h>
#include <mrpt/img/CImage.h>
#include <mrpt/opengl/CFBORender.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/opengl/stock_objects.h>
#include <pndt/app/map_outputs.h>
#include <pndt/mrpt/map_files.h>

#include <algorithm>
#include <cstdlib>

#include "voxel_mesh.h"

namespace pndt::app
{
namespace
{
/// Centre and size of the occupied part of the map.
void mapBounds(const PanopticMap& m, Eigen::Vector3d& centre, double& size)
{
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e18), hi = -lo;
    for (uint32_t i = 0; i < m.voxels().size(); ++i)
        if (m.isOccupied(m.voxels()[i]))
        {
            const Eigen::Vector3d c = m.grid().center(m.voxels().key(i));
            lo = lo.cwiseMin(c);
            hi = hi.cwiseMax(c);
        }
    if (lo.x() > hi.x()) lo = hi = Eigen::Vector3d::Zero();
    centre = 0.5 * (lo + hi);
    size = std::max(1.0, (hi - lo).norm());
}

mrpt::opengl::COpenGLScene::Ptr sceneOf(const PanopticNDTMap& map)
{
    auto scene = mrpt::opengl::COpenGLScene::Create();
    auto objs = mrpt::opengl::CSetOfObjects::Create();
    map.getVisualizationInto(*objs);
    scene->insert(objs);
    scene->insert(mrpt::opengl::stock_objects::CornerXYZSimple(0.5f, 2.0f));
    return scene;
}
}  // namespace

namespace
{
/// `scene` rendered off-screen looking at the map's centre, written as PNG atomically.
void renderToPng(const mrpt::opengl::COpenGLScene::Ptr& scene, const PanopticMap& map, const std::string& path,
                 int width, int height, double azimuth, double elevation, double zoom = 0.9)
{
    mrpt::opengl::CFBORender render{unsigned(width), unsigned(height)};
    Eigen::Vector3d c;
    double size;
    mapBounds(map, c, size);
    auto& cam = render.getCamera(*scene);
    cam.setPointingAt(float(c.x()), float(c.y()), float(c.z()));
    cam.setZoomDistance(float(zoom * size));
    cam.setAzimuthDegrees(float(azimuth));
    cam.setElevationDegrees(float(elevation));
    mrpt::img::CImage img;
    render.render_RGB(*scene, img);
    io::writeFileAtomically(path, [&](const std::string& tmp) {
        // CImage picks the format from the extension: keep it on the temporary.
        const std::string tmp_png = tmp + ".png";
        if (!img.saveToFile(tmp_png)) throw std::runtime_error("cannot write " + tmp_png);
        if (std::rename(tmp_png.c_str(), tmp.c_str()) != 0) throw std::runtime_error("cannot rename " + tmp_png);
    });
}
}  // namespace

void writeScreenshot(const PanopticNDTMap& map, const std::string& path, int width, int height, double azimuth,
                     double elevation)
{
    renderToPng(sceneOf(map), map.core(), path, width, height, azimuth, elevation);
}

void writeMeshScreenshot(const PanopticNDTMap& map, const std::string& path, int width, int height, double azimuth,
                         double elevation)
{
    auto scene = mrpt::opengl::COpenGLScene::Create();
    auto mesh = exposedFaceMesh(map.core());
    mesh->enableLight(false);  // the faces carry their own shading
    scene->insert(mesh);
    scene->insert(mrpt::opengl::stock_objects::CornerXYZSimple(0.5f, 2.0f));
    // Solid walls hide the room from a low camera: look from higher and further.
    renderToPng(scene, map.core(), path, width, height, azimuth, std::max(elevation, 55.0), 1.3);
}

bool showInteractive(const PanopticNDTMap& map)
{
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display) return false;
    mrpt::gui::CDisplayWindow3D win("PanopticNDT map", 1024, 768);
    Eigen::Vector3d c;
    double size;
    mapBounds(map.core(), c, size);
    {
        auto& scene = win.get3DSceneAndLock();
        scene = sceneOf(map);
        win.unlockAccess3DScene();
    }
    win.setCameraPointingToPoint(float(c.x()), float(c.y()), float(c.z()));
    win.setCameraZoom(float(0.9 * size));
    win.repaint();
    win.waitForKey();
    return true;
}
}  // namespace pndt::app
