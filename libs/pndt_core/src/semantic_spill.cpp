#include <pndt/semantic_spill.h>

#include <algorithm>

namespace pndt
{
void SemanticSpills::add(uint32_t label_record, LabelRecord& rec, uint8_t cls, float score)
{
    auto& h = rec.semantic;
    if (const int i = h.indexOf(cls); i >= 0)
    {
        h.setWeight(i, h.weight(i) + score);
        h.bubbleUp(i);
        return;
    }
    if (h.size() < LabelRecord::kSemanticCapacity)  // room in the record (a reset record)
    {
        h.add(cls, score);
        return;
    }
    SemanticSpill& spill = map_[label_record];
    auto it = std::find_if(spill.entries.begin(), spill.entries.end(),
                           [&](const SemanticSpill::Entry& e) { return e.cls == cls; });
    if (it == spill.entries.end()) it = spill.entries.insert(spill.entries.end(), {cls, 0.f});
    it->weight += score;
    constexpr int last = LabelRecord::kSemanticCapacity - 1;
    if (it->weight > h.weight(last))
    {
        // The class overtook the record's smallest entry: they trade places.
        const SemanticSpill::Entry out{uint8_t(h.ids[last]), h.weight(last)};
        h.ids[last] = cls;
        h.setWeight(last, it->weight);
        h.bubbleUp(last);
        *it = out;
    }
}

void SemanticSpills::set(uint32_t label_record, SemanticSpill spill)
{
    if (spill.entries.empty())
        map_.erase(label_record);
    else
        map_[label_record] = std::move(spill);
}

std::vector<std::pair<uint32_t, const SemanticSpill*>> SemanticSpills::sorted() const
{
    std::vector<std::pair<uint32_t, const SemanticSpill*>> out;
    out.reserve(map_.size());
    for (const auto& [rec, spill] : map_) out.emplace_back(rec, &spill);
    std::sort(out.begin(), out.end());
    return out;
}

size_t SemanticSpills::memoryBytes() const
{
    size_t bytes = map_.bucket_count() * (sizeof(std::pair<uint32_t, SemanticSpill>) + 4);
    for (const auto& [rec, spill] : map_) bytes += spill.entries.capacity() * sizeof(SemanticSpill::Entry);
    return bytes;
}

}  // namespace pndt
