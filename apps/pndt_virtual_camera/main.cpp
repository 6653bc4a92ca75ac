// pndt-virtual-camera: the OpenNI2 virtual camera's true poses as a TUM file (for
// pndt-pose-send), and how to point OpenNI2 at the driver.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <pndt/oni_virtual/virtual_scene.h>

int main(int argc, char** argv)
{
    CLI::App app{"pndt-virtual-camera: poses of the OpenNI2 virtual camera (libPndtVirtualCamera)"};
    std::string poses, config;
    app.add_option("--write-poses", poses, "write the camera's true optical-frame poses as TUM lines")->required();
    app.add_option("--config", config, "virtual camera configuration (default: $PNDT_VIRTUAL_CAMERA, else built-in)");
    CLI11_PARSE(app, argc, argv);
    try
    {
        const auto c = config.empty() ? pndt::oni_virtual::VirtualCameraConfig::fromEnvironment()
                                      : pndt::oni_virtual::VirtualCameraConfig::fromFile(config);
        pndt::oni_virtual::writeTrajectoryTum(c, poses);
        fmt::print("{}: {:.0f} s of poses at {} Hz (device stamps k/{})\n"
                   "camera: run with LD_LIBRARY_PATH={} so OpenNI2 loads the virtual camera driver{}\n",
                   poses, c.pose_seconds, c.fps, c.fps, PNDT_ONI_DIR,
                   config.empty() ? "" : fmt::format(" and PNDT_VIRTUAL_CAMERA={}", config));
    }
    catch (const std::exception& e)
    {
        fmt::print(stderr, "pndt-virtual-camera: error: {}\n", e.what());
        return 1;
    }
    return 0;
}
