// Plain-text questions about the map's objects, as a navigation app gets them:
//   "table"                            every table, largest first
//   "the table with the most chairs"   tables by chairs around them, most first
//   "a table with 8 chairs" / "eight"  tables with exactly that many chairs around
//   "table with chairs"                tables with at least one chair around
//   "the chair nearest to 1.5, -2"     chairs by distance to the point
//   "lamp on a table"                  lamps on top of some table
//   "chair next to the sofa"           chairs next to some sofa
//   "id 12"                            that instance
// Class names come from the map's class table (plurals accepted).
#pragma once

#include <pndt/nav/spatial_relations.h>

#include <string>
#include <vector>

namespace pndt::nav
{
enum class QueryKind
{
    Class,
    MostAround,
    FewestAround,
    CountAround,
    HasAround,
    Nearest,
    OnTopOf,
    NextTo,
    Id
};
const char* toString(QueryKind k);

struct QueryMatch
{
    const MapObject* object = nullptr;
    std::vector<uint32_t> related;  ///< ids: objects around it / it rests on / it is next to
    double distance = 0;            ///< Nearest: to the point (m)
};

struct QueryResult
{
    std::string query;
    QueryKind kind = QueryKind::Class;
    int target_class = -1;   ///< what is asked for
    int related_class = -1;  ///< what it is related to (chairs, the table it stands on)
    int count = -1;          ///< CountAround
    Eigen::Vector2d point = Eigen::Vector2d::Zero();  ///< Nearest
    std::vector<QueryMatch> matches;                  ///< best first; empty = no such object
    std::string summary;                              ///< one line for a person (why nothing matched, too)

    const MapObject* best() const { return matches.empty() ? nullptr : matches.front().object; }
};

/// Throws InputError for a query it cannot read, naming the problem: no known
/// class, a word that is neither a class of the map nor one of the query words
/// (an unknown class is not skipped: the answer would be about another object),
/// a relation without its second class, two classes without a relation, a
/// count or id that is not a whole number in range, a number that is not finite,
/// "nearest" without exactly two numbers for the point.
QueryResult runQuery(const std::vector<MapObject>& objects, const ClassSet& classes, const std::string& query,
                     const RelationOptions& relations = {});

}  // namespace pndt::nav
