#include "scores_output.h"

#include <fmt/format.h>
#include <pndt/eval/class_table.h>
#include <pndt/eval/markdown_table.h>

#include <cmath>

namespace pndt::evalapp
{
namespace
{
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

std::string summaryLine(const eval::EvalResult& r)
{
    return fmt::format("mIoU {:.1f}  mIoU_P {:.1f}  PQ {:.1f} (things {:.1f}, stuff {:.1f})  AP50 {:.1f}",
                       100 * r.semantic.miou, 100 * r.panoptic_semantic.miou, 100 * r.pq.all.pq, 100 * r.pq.things.pq,
                       100 * r.pq.stuff.pq, 100 * r.ap.ap50);
}

std::string classTable(const eval::EvalResult& r, const eval::Benchmark& bench)
{
    return eval::toMarkdown(eval::perClassTable(r, bench));
}

nlohmann::json scoresJson(const eval::EvalResult& r, const eval::Benchmark& bench)
{
    nlohmann::json j;
    j["miou"] = number(r.semantic.miou);
    j["miou_p"] = number(r.panoptic_semantic.miou);
    j["pq"] = number(r.pq.all.pq);
    j["sq"] = number(r.pq.all.sq);
    j["rq"] = number(r.pq.all.rq);
    j["pq_things"] = number(r.pq.things.pq);
    j["pq_stuff"] = number(r.pq.stuff.pq);
    j["ap"] = number(r.ap.ap);
    j["ap50"] = number(r.ap.ap50);
    j["ap25"] = number(r.ap.ap25);
    const eval::ClassTable t = eval::perClassTable(r, bench);
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : t.rows)
    {
        nlohmann::json c;
        c["id"] = row.id;
        c["name"] = row.name;
        c["thing"] = row.is_thing;
        for (size_t k = 0; k < t.columns.size(); ++k) c[t.columns[k]] = number(row.values[k]);
        rows.push_back(c);
    }
    j["classes"] = rows;
    return j;
}
}  // namespace pndt::evalapp
