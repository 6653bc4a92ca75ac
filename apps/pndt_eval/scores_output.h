// What pndt-eval prints and writes: the metrics of design §9 as text with a per-class
// table, and the same as JSON for machines.
#pragma once

#include <nlohmann/json.hpp>
#include <pndt/eval/benchmark.h>
#include <pndt/eval/panoptic_evaluator.h>

#include <string>

namespace pndt::evalapp
{
/// mIoU, mIoU_P, PQ (all / things / stuff), AP50 (confidence) in percent, one line.
std::string summaryLine(const eval::EvalResult& r);
/// The per-class table (IoU, IoU_P, PQ, SQ, RQ, AP50) as Markdown.
std::string classTable(const eval::EvalResult& r, const eval::Benchmark& bench);
/// The same numbers as JSON (fractions; NaN as null).
nlohmann::json scoresJson(const eval::EvalResult& r, const eval::Benchmark& bench);
}  // namespace pndt::evalapp
