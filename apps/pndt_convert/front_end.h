// pndt-convert --model: the segmentation front-end (pndt_seg) labelling each frame, with the
// counts and times the conversion report shows.
#pragma once

#include <pndt/seg/segmenter.h>

#include <memory>
#include <string>

#include "convert.h"

namespace pndt::convert
{
class FrontEnd
{
   public:
    /// Loads the model (errors name the description / network file). `up_world`: "x y z" or "".
    FrontEnd(const std::string& model_description, const std::string& up_world, ConvertReport& report);

    /// Labels `frame` (its depth and K are set) from the decoded RGB-D frame and its pose.
    void label(PanopticFrame& frame, const Image<seg::RgbPixel>* color, const Pose& T_world_cam);

   private:
    ClassSet classes_;
    std::unique_ptr<seg::Segmenter> segmenter_;
    ConvertReport& report_;
};

}  // namespace pndt::convert
