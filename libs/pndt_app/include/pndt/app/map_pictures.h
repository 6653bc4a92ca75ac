// Pictures of a map people can read: a class legend beside coloured renders, a top-down
// semantic floor plan with instance outlines and names, and a 3D view of the voxels'
// exposed faces (no inner faces, no gaps between cubes).
#pragma once

#include <opencv2/core.hpp>
#include <pndt/class_set.h>
#include <pndt/panoptic_map.h>

#include <string>
#include <vector>

namespace pndt::app
{
/// One line of a legend: a colour swatch and its text.
struct LegendEntry
{
    Rgb color;
    std::string text;
};

/// The classes seen in a labelled image (pixel counts per class id), most pixels first,
/// at most `max_entries` (void left out).
std::vector<LegendEntry> classLegend(const std::vector<uint64_t>& pixels_per_class, const ClassSet& classes,
                                     size_t max_entries = 24);

/// `image` (BGR) with the legend in a white panel on its right.
cv::Mat withLegend(const cv::Mat& image, const std::vector<LegendEntry>& entries);

/// Top-down floor plan (BGR): each cell of the x-y grid coloured by the class of its
/// highest occupied voxel below the ceiling (ceiling voxels left out, so the room shows),
/// instance outlines with "<class> <id>" at their centroids, a 1 m scale bar and a class
/// legend. `pixels_per_voxel` sets the scale.
cv::Mat floorPlan(const PanopticMap& map, int pixels_per_voxel = 8);

/// Writes a BGR image as PNG, atomically; throws naming the file.
void writePngFile(const cv::Mat& image, const std::string& path);

}  // namespace pndt::app
