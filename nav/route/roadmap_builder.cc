#include "nav/route/roadmap_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/math/rounding.h"

namespace pavilion::nav {
namespace {

using Vec2 = Eigen::Vector2d;

// Candidate edges join nodes at most this many via spacings apart; an edge is
// dropped when a detour over a third node is at most kDetourRatio as long.
constexpr double kMaxEdgeSpacings = 1.5;
constexpr double kDetourRatio = 1.05;
// Via nodes keep this many via spacings from other nodes.
constexpr double kMinNodeSpacings = 0.6;
// Edge weights never drop below this (m): MapEdge needs weight > 0.
constexpr double kMinEdgeWeightM = 1e-6;

std::string Numbered(const std::string& prefix, int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%03d", k);
  return prefix + buf;
}

// Undirected graph under construction.
struct Graph {
  std::vector<core::MapNode> nodes;
  std::set<std::pair<int, int>> edges;  // i < j

  void Add(int i, int j) { edges.insert(std::minmax(i, j)); }
  Vec2 At(int i) const { return nodes[i].pose.translation(); }

  // The root of each node's connected part.
  std::vector<int> Components() const {
    std::vector<int> parent(nodes.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
    const auto find = [&](int i) {
      while (parent[i] != i) i = parent[i] = parent[parent[i]];
      return i;
    };
    for (const auto& [a, b] : edges) parent[find(a)] = find(b);
    std::vector<int> out(nodes.size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = find(static_cast<int>(i));
    return out;
  }
};

// A grid path from one part of the graph to a node of another (JoinParts).
struct GridPath {
  std::map<std::size_t, int> node_at;  // the first node in each cell
  std::vector<std::int64_t> parent;    // breadth-first tree; -1 at the roots, -2 unvisited
  std::int64_t target = -1;            // the cell of the other part's node; -1 if none
};

class RoadmapBuilder {
 public:
  RoadmapBuilder(std::vector<core::MapNode> nodes, const FreeSpaceGrid& free,
                 const core::ObstacleSet& obstacles, const RoadmapOptions& options,
                 std::vector<std::string>& warnings)
      : free_(free), obstacles_(obstacles), options_(options), warn_(warnings) {
    graph_.nodes = std::move(nodes);
    for (const auto& n : graph_.nodes) node_ids_.insert(n.id);
  }

  Roadmap Build() {
    AddGridVias();
    AddEdges();
    JoinParts();
    WarnAboutGaps();
    Roadmap out;
    out.nodes = graph_.nodes;
    for (const auto& [a, b] : graph_.edges) {
      const double len = (graph_.At(a) - graph_.At(b)).norm();
      out.edges.push_back(
          {graph_.nodes[a].id, graph_.nodes[b].id,
           std::max(core::RoundDecimals(len, options_.position_decimals), kMinEdgeWeightM)});
    }
    return out;
  }

 private:
  bool Clear(const Vec2& a, const Vec2& b) const {
    return obstacles_.Clearance(a, b) >= options_.robot_radius_m;
  }

  // Cells a joining path may use: half a cell more than the robot radius, so
  // that straight hops between neighbouring cells stay clear.
  double Passable() const { return options_.robot_radius_m + free_.cell_m(); }

  int AddVia(const Vec2& p) {
    std::string id;
    do {
      id = Numbered("via_", ++via_count_);
    } while (node_ids_.contains(id));
    node_ids_.insert(id);
    const Vec2 q(core::RoundDecimals(p.x(), options_.position_decimals),
                 core::RoundDecimals(p.y(), options_.position_decimals));
    graph_.nodes.push_back({id, {q.x(), q.y(), 0.0}, false});
    return static_cast<int>(graph_.nodes.size()) - 1;
  }

  void WarnAboutGaps() {
    for (std::size_t k = 0; k < graph_.nodes.size(); ++k) {
      bool linked = false;
      for (const auto& [a, b] : graph_.edges) linked = linked || a == int(k) || b == int(k);
      if (!linked) {
        warn_.push_back(std::string(graph_.nodes[k].station ? "station" : "via") + " node '" +
                        graph_.nodes[k].id + "' has no collision-free edge");
      }
    }
    const std::vector<int> comp = graph_.Components();
    const std::set<int> roots(comp.begin(), comp.end());
    if (roots.size() > 1) {
      warn_.push_back("the graph has " + std::to_string(roots.size()) +
                      " separate parts (closed doors or unreachable places)");
    }
  }

  // The reachable cell of grid square (cx, cy) with the most clearance (capped
  // at half the pitch; ties to the square's centre); false when it has none.
  bool BestViaCell(int cx, int cy, int per, Vec2* best) const {
    const double spacing = options_.via_spacing_m;
    const double cell = free_.cell_m();
    const Vec2 centre = free_.Center(cx * per, cy * per) + 0.5 * (per - 1) * Vec2(cell, cell);
    double best_score = -1.0, best_dist = 0.0;
    for (int y = cy * per; y < std::min(free_.ny(), (cy + 1) * per); ++y) {
      for (int x = cx * per; x < std::min(free_.nx(), (cx + 1) * per); ++x) {
        const std::size_t i = free_.Index(x, y);
        if (!free_.reachable(i) || free_.clearance(i) < Passable()) continue;
        const double score = std::min(free_.clearance(i), 0.5 * spacing);
        const double dist = (free_.Center(x, y) - centre).norm();
        if (score > best_score + 1e-9 ||
            (std::abs(score - best_score) <= 1e-9 && dist < best_dist)) {
          best_score = score;
          best_dist = dist;
          *best = free_.Center(x, y);
        }
      }
    }
    return best_score >= 0.0;
  }

  // One via node per grid square at its best cell, unless crowded.
  void AddGridVias() {
    const double spacing = options_.via_spacing_m;
    const int per = std::max(1, static_cast<int>(std::lround(spacing / free_.cell_m())));
    for (int cy = 0; cy * per < free_.ny(); ++cy) {
      for (int cx = 0; cx * per < free_.nx(); ++cx) {
        Vec2 best;
        if (!BestViaCell(cx, cy, per, &best)) continue;
        bool crowded = false;
        for (const auto& n : graph_.nodes) {
          crowded = crowded || (n.pose.translation() - best).norm() < kMinNodeSpacings * spacing;
        }
        if (!crowded) AddVia(best);
      }
    }
  }

  // Clear straight edges between near nodes, without the ones a two-edge
  // detour nearly matches (longest first).
  void AddEdges() {
    std::vector<std::pair<double, std::pair<int, int>>> candidates;
    const int n = static_cast<int>(graph_.nodes.size());
    for (int i = 0; i < n; ++i) {
      for (int j = i + 1; j < n; ++j) {
        const double len = (graph_.At(i) - graph_.At(j)).norm();
        if (len <= kMaxEdgeSpacings * options_.via_spacing_m && Clear(graph_.At(i), graph_.At(j))) {
          candidates.push_back({len, {i, j}});
          graph_.Add(i, j);
        }
      }
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) {
      return x.first != y.first ? x.first > y.first : x.second < y.second;
    });
    std::vector<std::set<int>> adjacent(graph_.nodes.size());
    for (const auto& [a, b] : graph_.edges) {
      adjacent[a].insert(b);
      adjacent[b].insert(a);
    }
    for (const auto& [len, ij] : candidates) {
      const auto [i, j] = ij;
      for (int k : adjacent[i]) {
        if (k == j || !adjacent[k].contains(j)) continue;
        if ((graph_.At(i) - graph_.At(k)).norm() + (graph_.At(k) - graph_.At(j)).norm() <=
            kDetourRatio * len) {
          adjacent[i].erase(j);
          adjacent[j].erase(i);
          graph_.edges.erase({i, j});
          break;
        }
      }
    }
  }

  // Breadth-first search (8-connected) over passable reachable cells from the
  // nodes of part `root` to the nearest cell holding a node of another part.
  GridPath SearchFrom(const std::vector<int>& comp, int root) const {
    GridPath g;
    for (std::size_t k = 0; k < graph_.nodes.size(); ++k) {
      std::size_t cell;
      if (free_.CellOf(graph_.At(static_cast<int>(k)), &cell)) g.node_at.try_emplace(cell, k);
    }
    g.parent.assign(static_cast<std::size_t>(free_.nx()) * free_.ny(), -2);
    std::deque<std::size_t> queue;
    for (std::size_t k = 0; k < graph_.nodes.size(); ++k) {
      std::size_t cell;
      if (comp[k] == root && free_.CellOf(graph_.At(static_cast<int>(k)), &cell) &&
          g.parent[cell] == -2) {
        g.parent[cell] = -1;
        queue.push_back(cell);
      }
    }
    while (!queue.empty() && g.target < 0) {
      const std::size_t i = queue.front();
      queue.pop_front();
      const int x = static_cast<int>(i % free_.nx()), y = static_cast<int>(i / free_.nx());
      for (int dy = -1; dy <= 1 && g.target < 0; ++dy) {
        for (int dx = -1; dx <= 1 && g.target < 0; ++dx) {
          const int u = x + dx, v = y + dy;
          if ((dx == 0 && dy == 0) || u < 0 || v < 0 || u >= free_.nx() || v >= free_.ny()) {
            continue;
          }
          const std::size_t j = free_.Index(u, v);
          if (g.parent[j] != -2) continue;
          const auto hit = g.node_at.find(j);
          if (hit != g.node_at.end() && comp[hit->second] != root) {
            g.parent[j] = static_cast<std::int64_t>(i);
            g.target = static_cast<std::int64_t>(j);
            break;
          }
          if (!free_.reachable(j) || free_.clearance(j) < Passable()) continue;
          g.parent[j] = static_cast<std::int64_t>(i);
          queue.push_back(j);
        }
      }
    }
    return g;
  }

  // Joins the parts of the graph that the reachable floor connects: a grid path
  // from one part to the nearest node of another, shortened to straight
  // collision-free hops whose corners become via nodes.
  void JoinParts() {
    std::set<int> stuck;  // parts (by root) that reach no other part
    for (;;) {
      const std::vector<int> comp = graph_.Components();
      const std::set<int> roots(comp.begin(), comp.end());
      if (roots.size() <= 1) return;
      bool joined = false;
      for (int root : roots) {
        if (stuck.contains(root)) continue;
        const GridPath g = SearchFrom(comp, root);
        if (g.target < 0 || !Bridge(comp, root, g)) {
          stuck.insert(root);
          continue;
        }
        joined = true;
        break;
      }
      if (!joined) return;
    }
  }

  // Adds the hops of the grid path `g` (found by SearchFrom); false when its
  // first hop is not clear.
  bool Bridge(const std::vector<int>& comp, int root, const GridPath& g) {
    std::vector<std::size_t> cells;
    for (std::int64_t c = g.target; c >= 0; c = g.parent[static_cast<std::size_t>(c)]) {
      cells.push_back(static_cast<std::size_t>(c));
    }
    std::reverse(cells.begin(), cells.end());
    int start = -1;
    for (std::size_t k = 0; k < graph_.nodes.size() && start < 0; ++k) {
      std::size_t cell;
      if (comp[k] == root && free_.CellOf(graph_.At(static_cast<int>(k)), &cell) &&
          cell == cells.front()) {
        start = static_cast<int>(k);
      }
    }
    const int end = g.node_at.at(cells.back());
    std::vector<Vec2> path = {graph_.At(start)};
    for (std::size_t k = 1; k + 1 < cells.size(); ++k) path.push_back(free_.Center(cells[k]));
    path.push_back(graph_.At(end));
    // Straight hops, each as long as it stays clear.
    std::vector<std::size_t> hops = {0};
    while (hops.back() + 1 < path.size()) {
      std::size_t j = hops.back() + 1;
      if (!Clear(path[hops.back()], path[j])) return false;
      while (j + 1 < path.size() && Clear(path[hops.back()], path[j + 1])) ++j;
      hops.push_back(j);
    }
    int previous = start;
    for (std::size_t k = 1; k < hops.size(); ++k) {
      const int node = hops[k] + 1 == path.size() ? end : AddVia(path[hops[k]]);
      graph_.Add(previous, node);
      previous = node;
    }
    return true;
  }

  const FreeSpaceGrid& free_;
  const core::ObstacleSet& obstacles_;
  const RoadmapOptions& options_;
  std::vector<std::string>& warn_;
  Graph graph_;
  std::set<std::string> node_ids_;
  int via_count_ = 0;
};

}  // namespace

void RoadmapOptions::Validate() const {
  if (!(robot_radius_m > 0.0) || !std::isfinite(robot_radius_m)) {
    throw std::invalid_argument("RoadmapOptions.robot_radius_m must be finite and > 0");
  }
  if (!(via_spacing_m > 0.0) || !std::isfinite(via_spacing_m)) {
    throw std::invalid_argument("RoadmapOptions.via_spacing_m must be finite and > 0");
  }
  if (position_decimals < 0) {
    throw std::invalid_argument("RoadmapOptions.position_decimals must be >= 0");
  }
}

Roadmap BuildRoadmap(std::vector<core::MapNode> nodes, const FreeSpaceGrid& free,
                     const core::ObstacleSet& obstacles, const RoadmapOptions& options,
                     std::vector<std::string>* warnings) {
  options.Validate();
  std::vector<std::string> ignored;
  return RoadmapBuilder(std::move(nodes), free, obstacles, options,
                        warnings != nullptr ? *warnings : ignored)
      .Build();
}

}  // namespace pavilion::nav
