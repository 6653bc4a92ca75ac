// NYUv2-40 semantic class ids used by the synthetic scenes (0 = void). Their
// names and stuff/thing split for users: pndt::ClassSet::nyuv2_40() (pndt_core).
#pragma once

#include <cstdint>

namespace pndt::sim::nyu40
{
constexpr uint16_t kVoid = 0;
constexpr uint16_t kWall = 1;
constexpr uint16_t kFloor = 2;
constexpr uint16_t kCabinet = 3;
constexpr uint16_t kBed = 4;
constexpr uint16_t kChair = 5;
constexpr uint16_t kSofa = 6;
constexpr uint16_t kTable = 7;
constexpr uint16_t kDoor = 8;
constexpr uint16_t kWindow = 9;
constexpr uint16_t kBookshelf = 10;
constexpr uint16_t kDesk = 14;
constexpr uint16_t kShelves = 15;
constexpr uint16_t kCeiling = 22;
constexpr uint16_t kLamp = 35;
constexpr uint16_t kOtherStructure = 38;
constexpr uint16_t kOtherFurniture = 39;
constexpr uint16_t kOtherProp = 40;

/// Number of classes including void (ids 0..40).
constexpr int kNumClasses = 41;

}  // namespace pndt::sim::nyu40
