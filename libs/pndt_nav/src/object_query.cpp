// Reading and answering object queries (object_query.h).
#include <fmt/format.h>
#include <pndt/nav/object_query.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <set>

namespace pndt::nav
{
const char* toString(QueryKind k)
{
    switch (k)
    {
        case QueryKind::Class: return "class";
        case QueryKind::MostAround: return "most_around";
        case QueryKind::FewestAround: return "fewest_around";
        case QueryKind::CountAround: return "count_around";
        case QueryKind::HasAround: return "has_around";
        case QueryKind::Nearest: return "nearest";
        case QueryKind::OnTopOf: return "on_top_of";
        case QueryKind::NextTo: return "next_to";
        case QueryKind::Id: return "id";
    }
    return "?";
}

namespace
{
std::vector<std::string> tokenize(const std::string& q)
{
    std::string s;
    for (char c : q)
    {
        const unsigned char u = static_cast<unsigned char>(c);
        s += (std::isalnum(u) || c == '.' || c == '-' || c == '#') ? char(std::tolower(u)) : ' ';
    }
    std::vector<std::string> out;
    size_t i = 0;
    while (i < s.size())
    {
        while (i < s.size() && s[i] == ' ') ++i;
        size_t j = i;
        while (j < s.size() && s[j] != ' ') ++j;
        if (j > i)
        {
            std::string t = s.substr(i, j - i);
            if (t.front() == '#') t.erase(0, 1);
            while (!t.empty() && t.back() == '.') t.pop_back();  // end of sentence
            if (!t.empty()) out.push_back(t);
        }
        i = j;
    }
    return out;
}

/// A number word or a finite decimal number; "nan", "inf" and "1e400" are not
/// numbers here (they would answer a question nobody can have meant).
std::optional<double> number(const std::string& t)
{
    static const char* words[] = {"zero", "one", "two",   "three",  "four",  "five",  "six",
                                  "seven", "eight", "nine", "ten", "eleven", "twelve"};
    for (int i = 0; i <= 12; ++i)
        if (t == words[i]) return double(i);
    if (t.empty() || !(std::isdigit(static_cast<unsigned char>(t[0])) || t[0] == '-' || t[0] == '.')) return std::nullopt;
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end && *end == 0 && end != t.c_str() && std::isfinite(v)) return v;
    return std::nullopt;
}

/// A whole number in [lo, hi], or nullopt.
std::optional<uint64_t> wholeNumber(double v, double lo, double hi)
{
    if (v < lo || v > hi || v != std::floor(v)) return std::nullopt;
    return uint64_t(v);
}

// The relation words, once: read by runQuery and accepted by isQueryWord.
using Words = std::initializer_list<const char*>;
constexpr Words kMostWords{"most", "more", "many"};
constexpr Words kFewestWords{"fewest", "least", "fewer", "less"};
constexpr Words kWithWords{"with", "has", "have", "having"};
constexpr Words kOnWords{"on", "onto", "atop", "top"};
constexpr Words kNextWords{"next", "beside", "by", "near"};
constexpr Words kNearestWords{"nearest", "closest", "near"};

/// The words a query may hold besides class names and numbers. A word outside
/// this list is most likely a class the map does not have ("the unicorn with
/// the most chairs"): answering without it would send the robot to another object.
bool isQueryWord(const std::string& w)
{
    static const std::set<std::string> words = {
        // articles, pronouns, fillers
        "a", "an", "the", "any", "some", "it", "its", "them", "they", "there", "that", "which", "who",
        "this", "these", "those", "is", "are", "be", "me", "my", "i", "you", "please", "and", "of", "at", "in",
        "for", "from", "around", "round", "about", "exactly", "just", "only", "where", "what", "whichever",
        // what a robot is told to do
        "go", "drive", "move", "navigate", "head", "get", "take", "bring", "find", "show", "look", "locate",
        "to", "towards", "toward", "into", "point",
        // a point's axes and unit; ids
        "close", "x", "y", "m", "metres", "meters", "id", "object", "instance", "number"};
    if (words.count(w)) return true;
    for (const Words list : {kMostWords, kFewestWords, kWithWords, kOnWords, kNextWords, kNearestWords})
        for (const char* r : list)
            if (w == r) return true;
    return false;
}

struct ClassMention
{
    size_t pos = 0, len = 0;
    int id = -1;
};

/// Class names at every position, longest first (three words down to one).
std::vector<ClassMention> classMentions(const std::vector<std::string>& t, const ClassSet& classes)
{
    std::vector<ClassMention> out;
    for (size_t i = 0; i < t.size();)
    {
        bool found = false;
        for (size_t len = std::min<size_t>(3, t.size() - i); len >= 1 && !found; --len)
        {
            std::string phrase = t[i];
            for (size_t k = 1; k < len; ++k) phrase += " " + t[i + k];
            if (number(phrase)) continue;  // "5" is a count, not class 5
            const int id = classIdFromName(classes, phrase);
            if (id > 0)
            {
                out.push_back({i, len, id});
                i += len;
                found = true;
            }
        }
        if (!found) ++i;
    }
    return out;
}

bool hasWord(const std::vector<std::string>& t, size_t from, size_t to, Words words)
{
    for (size_t i = from; i < std::min(to, t.size()); ++i)
        for (const char* w : words)
            if (t[i] == w) return true;
    return false;
}

std::string className(const ClassSet& c, int id) { return c.contains(uint32_t(id)) ? c.name(uint32_t(id)) : "?"; }

/// "chair" -> "chairs" unless there is one; names ending in s stay (shelves, books).
std::string plural(const std::string& name, size_t n = 2)
{
    if (n == 1 || name.empty() || name.back() == 's') return name;
    const bool es = name.back() == 'x' || (name.size() > 1 && (name.compare(name.size() - 2, 2, "ch") == 0 ||
                                                               name.compare(name.size() - 2, 2, "sh") == 0));
    return name + (es ? "es" : "s");
}

std::string knownClasses(const ClassSet& classes)
{
    std::string s;
    for (size_t i = 1; i < classes.size(); ++i) s += (s.empty() ? "" : ", ") + classes.name(uint32_t(i));
    return s;
}
}  // namespace

QueryResult runQuery(const std::vector<MapObject>& objects, const ClassSet& classes, const std::string& query,
                     const RelationOptions& rel)
{
    QueryResult r;
    r.query = query;
    const std::vector<std::string> t = tokenize(query);
    if (t.empty()) throw InputError("empty query");

    // "id 12" / "object 12" / "#12"
    for (size_t i = 0; i + 1 < t.size(); ++i)
        if ((t[i] == "id" || t[i] == "object" || t[i] == "instance") && number(t[i + 1]))
        {
            r.kind = QueryKind::Id;
            const auto whole = wholeNumber(*number(t[i + 1]), 0, double(UINT32_MAX));
            if (!whole)
                throw InputError(fmt::format("'{}': an instance id is a whole number from 0 to {}, not {}", query,
                                             UINT32_MAX, t[i + 1]));
            const uint32_t id = uint32_t(*whole);
            if (const MapObject* o = findObject(objects, id)) r.matches.push_back({o, {}, 0});
            r.summary = r.matches.empty() ? fmt::format("no object with id {}", id)
                                          : fmt::format("object {} is a {}", id, r.matches[0].object->class_name);
            return r;
        }

    const std::vector<ClassMention> mentions = classMentions(t, classes);
    if (mentions.empty())
        throw InputError(fmt::format("no known class in the query '{}' (the map's classes: {})", query,
                                     knownClasses(classes)));
    // Every word is read: a class, a number or a word of the query language.
    std::vector<bool> is_class(t.size(), false);
    for (const ClassMention& m : mentions)
        for (size_t k = 0; k < m.len; ++k) is_class[m.pos + k] = true;
    for (size_t i = 0; i < t.size(); ++i)
    {
        if (is_class[i] || number(t[i]) || isQueryWord(t[i])) continue;
        char* end = nullptr;
        std::strtod(t[i].c_str(), &end);
        if (end && *end == 0 && end != t[i].c_str())
            throw InputError(fmt::format("'{}': '{}' is not a finite number", query, t[i]));
        throw InputError(fmt::format("'{}': '{}' is not a class of the map nor a word queries use (the map's "
                                     "classes: {})",
                                     query, t[i], knownClasses(classes)));
    }
    if (mentions.size() > 2)
        throw InputError(fmt::format("'{}': more than two classes ({}, {}, {}); a query relates one class to one other",
                                     query, className(classes, mentions[0].id), className(classes, mentions[1].id),
                                     className(classes, mentions[2].id)));
    const ClassMention a = mentions[0];
    const bool has_b = mentions.size() > 1;
    const ClassMention b = has_b ? mentions[1] : ClassMention{};
    r.target_class = a.id;
    const std::string A = className(classes, a.id);
    std::vector<double> numbers;
    std::optional<int> count_between;
    for (size_t i = 0; i < t.size(); ++i)
        if (const auto v = number(t[i]))
        {
            numbers.push_back(*v);
            if (has_b && i > a.pos && i < b.pos)
            {
                const auto whole = wholeNumber(*v, 0, 100000);
                if (!whole)
                    throw InputError(fmt::format("'{}': a count of {} is a whole number from 0 to 100000, not {}",
                                                 query, plural(className(classes, b.id)), t[i]));
                count_between = int(*whole);
            }
        }
    const bool relation_word =
        hasWord(t, 0, t.size(), kWithWords) || hasWord(t, 0, t.size(), kMostWords) ||
        hasWord(t, 0, t.size(), kFewestWords) || hasWord(t, 0, t.size(), kOnWords) ||
        (hasWord(t, 0, t.size(), kNextWords) && !hasWord(t, 0, t.size(), kNearestWords));
    if (!has_b && relation_word)
        throw InputError(fmt::format("'{}': a relation without its second class (e.g. '{} with the most chairs', "
                                     "'{} next to a table')",
                                     query, A, A));
    std::vector<const MapObject*> of_a;
    for (const MapObject& o : objects)
        if (o.class_id == a.id) of_a.push_back(&o);

    const bool nearest_word = hasWord(t, 0, t.size(), kNearestWords);
    if (has_b)
    {
        r.related_class = b.id;
        const std::string B = className(classes, b.id);
        const size_t from = a.pos + a.len, to = b.pos;
        const bool most = hasWord(t, 0, to, kMostWords), fewest = hasWord(t, 0, to, kFewestWords);
        if (most || fewest || count_between || hasWord(t, from, to, kWithWords))
        {
            const auto around = objectsAround(objects, a.id, b.id, rel);
            for (const MapObject* o : of_a) r.matches.push_back({o, around.at(o->id), 0});
            std::stable_sort(r.matches.begin(), r.matches.end(), [&](const QueryMatch& x, const QueryMatch& y) {
                return fewest ? x.related.size() < y.related.size() : x.related.size() > y.related.size();
            });
            std::string counts;
            for (const QueryMatch& m : r.matches)
                counts += fmt::format("{}{} {}: {}", counts.empty() ? "" : ", ", A, m.object->id, m.related.size());
            if (most || fewest)
            {
                r.kind = most ? QueryKind::MostAround : QueryKind::FewestAround;
                r.summary = r.matches.empty()
                                ? fmt::format("the map has no {}", A)
                                : fmt::format("{} {} has {} {} around it ({} around each {}: {})", A, r.best()->id,
                                              r.matches[0].related.size(), plural(B, r.matches[0].related.size()),
                                              plural(B), A, counts);
            }
            else
            {
                r.kind = count_between ? QueryKind::CountAround : QueryKind::HasAround;
                r.count = count_between.value_or(-1);
                r.matches.erase(std::remove_if(r.matches.begin(), r.matches.end(),
                                               [&](const QueryMatch& m) {
                                                   return count_between ? int(m.related.size()) != *count_between
                                                                        : m.related.empty();
                                               }),
                                r.matches.end());
                const std::string wanted = count_between ? std::to_string(*count_between) : "any";
                r.summary = r.matches.empty()
                                ? fmt::format("no {} with {} {} around it ({} around each {}: {})", A, wanted,
                                              plural(B, size_t(count_between.value_or(2))), plural(B), A,
                                              counts.empty() ? "none" : counts)
                                : fmt::format("{} {} with {} {} around ({} around each {}: {})", r.matches.size(),
                                              plural(A, r.matches.size()), wanted, plural(B), plural(B), A, counts);
            }
            return r;
        }
        if (hasWord(t, from, to, kOnWords) || hasWord(t, from, to, kNextWords))
        {
            const bool on_top = hasWord(t, from, to, kOnWords);
            r.kind = on_top ? QueryKind::OnTopOf : QueryKind::NextTo;
            for (const MapObject* o : of_a)
            {
                QueryMatch m{o, {}, 0};
                for (const MapObject& other : objects)
                    if (other.class_id == b.id &&
                        (on_top ? isOnTopOf(*o, other, rel) : isNextTo(*o, other, rel)))
                        m.related.push_back(other.id);
                if (!m.related.empty()) r.matches.push_back(m);
            }
            r.summary = fmt::format("{} {} {} a {}", r.matches.size(), plural(A, r.matches.size()),
                                    on_top ? "on top of" : "next to", B);
            return r;
        }
    }
    if (has_b)
        throw InputError(fmt::format("'{}': how is the {} related to the {}? (with / most / fewest / N ... around, "
                                     "on, next to)",
                                     query, A, className(classes, b.id)));
    if (nearest_word)
    {
        if (numbers.size() != 2)
            throw InputError(fmt::format("'{}': nearest to what? give a point as two numbers (x y, metres){}", query,
                                         numbers.size() > 2 ? fmt::format(", not {}", numbers.size()) : ""));
        r.kind = QueryKind::Nearest;
        r.point = {numbers[0], numbers[1]};
        for (const auto& [o, d] : nearestTo(objects, a.id, r.point)) r.matches.push_back({o, {}, d});
        r.summary = r.matches.empty() ? fmt::format("the map has no {}", A)
                                      : fmt::format("{} {} is nearest to ({:.2f}, {:.2f}): {:.2f} m", A, r.best()->id,
                                                    r.point.x(), r.point.y(), r.matches[0].distance);
        return r;
    }
    r.kind = QueryKind::Class;
    for (const MapObject* o : of_a) r.matches.push_back({o, {}, 0});
    std::stable_sort(r.matches.begin(), r.matches.end(),
                     [](const QueryMatch& x, const QueryMatch& y) { return x.object->voxel_count > y.object->voxel_count; });
    r.summary = fmt::format("{} {} in the map", r.matches.size(), plural(A, r.matches.size()));
    return r;
}

}  // namespace pndt::nav
