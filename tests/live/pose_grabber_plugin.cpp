// A CGenericSensor whose observations are CObservationRobotPose, built as an MRPT plug-in
// module: MRPT 2.5.8 has no built-in sensor class producing robot poses, so pndt-live's
// --pose-grabber needs a class of the user's own, loaded through the grabber section's
// `plugin` key (mrpt::system::loadPluginModules). This one replays a TUM file of optical
// camera poses (`file`) as robot poses in the MRPT frame (camera_pose identity), `rate` poses
// a second (0 = all at once), with a CObservationComment after each pose (not a pose: must be
// ignored). `fail_initialize = true` makes initialize() throw.
#include <mrpt/core/exceptions.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationRobotPose.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/system/datetime.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <vector>

namespace pndt_test
{
class PndtTestPoseGrabber : public mrpt::hwdrivers::CGenericSensor
{
    DEFINE_GENERIC_SENSOR(PndtTestPoseGrabber)

   public:
    void initialize() override
    {
        if (fail_) THROW_EXCEPTION("told to fail (fail_initialize)");
        std::ifstream in(file_);
        if (!in) THROW_EXCEPTION_FMT("cannot open %s", file_.c_str());
        // Optical axes (x right, y down, z forward) in the MRPT sensor frame (x forward, z up).
        const mrpt::poses::CPose3D optical(0, 0, 0, -M_PI / 2, 0, -M_PI / 2);
        std::string line;
        while (std::getline(in, line))
        {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream s(line);
            double t, x, y, z, qx, qy, qz, qw;
            if (!(s >> t >> x >> y >> z >> qx >> qy >> qz >> qw)) continue;
            const mrpt::poses::CPose3D cam(mrpt::poses::CPose3DQuat(x, y, z, mrpt::math::CQuaternionDouble(qw, qx, qy, qz)));
            auto o = std::make_shared<mrpt::obs::CObservationRobotPose>();
            o->sensorLabel = "TEST_POSES";
            o->timestamp = mrpt::Clock::fromDouble(t);
            o->pose.mean = cam + (-optical);  // robot (= sensor) pose whose optical frame is `cam`
            poses_.push_back(o);
        }
        t0_ = std::chrono::steady_clock::now();
    }
    void doProcess() override
    {
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
        const size_t due = rate_ > 0 ? std::min(poses_.size(), size_t(dt * rate_) + 1) : poses_.size();
        std::vector<mrpt::serialization::CSerializable::Ptr> out;
        for (; next_ < due; ++next_)
        {
            out.push_back(poses_[next_]);
            auto c = std::make_shared<mrpt::obs::CObservationComment>();
            c->text = "not a pose";
            c->timestamp = poses_[next_]->timestamp;
            out.push_back(c);
        }
        if (!out.empty()) appendObservations(out);
    }

   protected:
    void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& c, const std::string& section) override
    {
        file_ = c.read_string(section, "file", "", true);
        rate_ = c.read_double(section, "rate", 0);
        fail_ = c.read_bool(section, "fail_initialize", false);
    }

   private:
    std::string file_;
    double rate_ = 0;
    bool fail_ = false;
    std::vector<mrpt::obs::CObservationRobotPose::Ptr> poses_;
    size_t next_ = 0;
    std::chrono::steady_clock::time_point t0_;
};
IMPLEMENTS_GENERIC_SENSOR(PndtTestPoseGrabber, pndt_test)

namespace
{
struct Register
{
    Register() { PndtTestPoseGrabber::doRegister(); }
} register_on_load;
}  // namespace
}  // namespace pndt_test
