#include "nav/local/nf1.h"

#include <cmath>

namespace pavilion::nav {

namespace {

// Internal value of a cell that is not free (and of the one-cell border);
// free cells not yet reached hold kUnreachable.
constexpr std::int32_t kBlocked = Nf1Planner::kUnreachable - 1;

// The 8 descent moves: the 4-connected ones first (E, N, W, S), then the
// diagonals (NE, NW, SW, SE); the order is the descent's tie-break.
constexpr int kMoves = 8;
constexpr int kFourConnected = 4;
constexpr int kMoveDx[kMoves] = {1, 0, -1, 0, 1, -1, -1, 1};
constexpr int kMoveDy[kMoves] = {0, 1, 0, -1, 1, 1, -1, -1};

// `p` lies on the grid's square (checked in doubles, so a far goal never
// reaches the integer cell conversion).
bool OnGrid(const LocalGrid& grid, const Eigen::Vector2d& p_in_world) {
  if (!p_in_world.allFinite()) return false;
  const Eigen::Vector2d q = (p_in_world - grid.origin()) / grid.cell_m();
  const double n = grid.cells_per_side();
  return q.x() >= 0.0 && q.y() >= 0.0 && q.x() < n && q.y() < n;
}

}  // namespace

void Nf1Planner::Compute(const LocalGrid& grid, const GridCell& goal) {
  n_ = grid.cells_per_side();
  stride_ = n_ + 2;
  const std::size_t padded = static_cast<std::size_t>(stride_) * stride_;
  if (values_.size() != padded) {
    values_.assign(padded, kBlocked);  // the border stays blocked
    queue_.assign(static_cast<std::size_t>(n_) * n_, 0);
  }
  for (int y = 0; y < n_; ++y) {
    std::int32_t* row = values_.data() + (y + 1) * stride_ + 1;
    for (int x = 0; x < n_; ++x) row[x] = grid.Free(GridCell(x, y)) ? kUnreachable : kBlocked;
  }
  if (!grid.Free(goal)) return;

  // Breadth-first wavefront; every cell enters the ring at most once.
  const std::int32_t offsets[kFourConnected] = {1, -1, stride_, -stride_};
  const std::size_t capacity = queue_.size();
  std::size_t head = 0;
  std::size_t tail = 0;
  std::size_t count = 0;
  const std::int32_t goal_index = PaddedIndex(goal);
  values_[goal_index] = 0;
  queue_[tail++] = goal_index;
  ++count;
  while (count > 0) {
    const std::int32_t i = queue_[head];
    head = head + 1 == capacity ? 0 : head + 1;
    --count;
    const std::int32_t next = values_[i] + 1;
    for (const std::int32_t offset : offsets) {
      const std::int32_t j = i + offset;
      if (values_[j] != kUnreachable) continue;
      values_[j] = next;
      queue_[tail] = j;
      tail = tail + 1 == capacity ? 0 : tail + 1;
      ++count;
    }
  }
}

std::int32_t Nf1Planner::value(const GridCell& cell) const {
  if (cell.x() < 0 || cell.y() < 0 || cell.x() >= n_ || cell.y() >= n_) return kUnreachable;
  const std::int32_t v = values_[PaddedIndex(cell)];
  return v >= kBlocked ? kUnreachable : v;
}

std::optional<GridCell> Nf1Planner::StartCell(const LocalGrid& grid, const Eigen::Vector2d& start) {
  if (!OnGrid(grid, start)) return std::nullopt;
  const GridCell cell = grid.CellOf(start);
  if (grid.Free(cell)) return cell;
  const double radius_m = grid.options().robot_radius_m;
  const int reach = static_cast<int>(std::ceil(radius_m / grid.cell_m())) + 1;
  std::optional<GridCell> best;
  double best_d2 = radius_m * radius_m;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const GridCell q = cell + GridCell(dx, dy);
      if (!grid.Free(q)) continue;
      const double d2 = (grid.CenterOf(q) - start).squaredNorm();
      if (d2 < best_d2 || (!best && d2 == best_d2)) {
        best = q;
        best_d2 = d2;
      }
    }
  }
  return best;
}

std::optional<Eigen::Vector2d> Nf1Planner::LocalGoal(const LocalGrid& grid,
                                                     const Eigen::Vector2d& start,
                                                     const Eigen::Vector2d& goal) {
  const std::optional<GridCell> start_cell = StartCell(grid, start);
  if (!start_cell) return std::nullopt;
  Nf1Planner planner;
  return planner.SelectLocalGoal(grid, *start_cell, goal);
}

std::optional<Eigen::Vector2d> Nf1Planner::SelectLocalGoal(const LocalGrid& grid,
                                                           const GridCell& start_cell,
                                                           const Eigen::Vector2d& goal) {
  if (!grid.Free(start_cell)) return std::nullopt;
  if (OnGrid(grid, goal)) {
    const GridCell goal_cell = grid.CellOf(goal);
    if (grid.Free(goal_cell)) {
      Compute(grid, goal_cell);
      if (value(start_cell) != kUnreachable) return goal;
    }
  }
  // The wavefront from the start marks what is reachable; the nearest such
  // cell to the goal (first in index order on ties) becomes the goal.
  Compute(grid, start_cell);
  GridCell best = start_cell;
  double best_d2 = (grid.CenterOf(start_cell) - goal).squaredNorm();
  for (int y = 0; y < n_; ++y) {
    const std::int32_t* row = values_.data() + (y + 1) * stride_ + 1;
    for (int x = 0; x < n_; ++x) {
      if (row[x] >= kBlocked) continue;
      const double d2 = (grid.CenterOf(GridCell(x, y)) - goal).squaredNorm();
      if (d2 < best_d2) {
        best = GridCell(x, y);
        best_d2 = d2;
      }
    }
  }
  Compute(grid, best);
  return grid.CenterOf(best);
}

bool Nf1Planner::Descend(const GridCell& start_cell) {
  cell_path_.clear();
  std::int32_t i = PaddedIndex(start_cell);
  std::int32_t v = values_[i];
  if (v >= kBlocked) return false;
  std::int32_t offsets[kMoves];
  for (int k = 0; k < kMoves; ++k) offsets[k] = kMoveDy[k] * stride_ + kMoveDx[k];
  GridCell cell = start_cell;
  cell_path_.push_back(cell);
  int previous = -1;
  while (v > 0) {
    int best = -1;
    std::int32_t best_v = v;
    const auto consider = [&](int k) {
      const std::int32_t vk = values_[i + offsets[k]];
      if (vk >= best_v) return;
      // A diagonal passes between its two 4-neighbours: both must be reached.
      if (k >= kFourConnected &&
          (values_[i + kMoveDx[k]] >= kBlocked || values_[i + kMoveDy[k] * stride_] >= kBlocked)) {
        return;
      }
      best = k;
      best_v = vk;
    };
    if (previous >= 0) consider(previous);
    for (int k = 0; k < kMoves; ++k) {
      if (k != previous) consider(k);
    }
    // A reached cell with value v > 0 has a 4-neighbour at v - 1.
    i += offsets[best];
    v = best_v;
    cell += GridCell(kMoveDx[best], kMoveDy[best]);
    cell_path_.push_back(cell);
    previous = best;
  }
  return true;
}

std::optional<std::vector<Eigen::Vector2d>> Nf1Planner::Plan(const LocalGrid& grid,
                                                             const Eigen::Vector2d& start,
                                                             const Eigen::Vector2d& goal,
                                                             std::uint64_t /*seed*/) {
  const std::optional<GridCell> start_cell = StartCell(grid, start);
  if (!start_cell) return std::nullopt;
  const std::optional<Eigen::Vector2d> local_goal = SelectLocalGoal(grid, *start_cell, goal);
  // The seam's contract: a path to `goal` itself or none; the caller picks a
  // reachable local goal first (LocalGoal).
  if (!local_goal || *local_goal != goal || !Descend(*start_cell)) return std::nullopt;

  std::vector<Eigen::Vector2d> path;
  path.push_back(start);
  // A start off its free cell (grazing) first returns to that cell's centre.
  if (grid.CellOf(start) != *start_cell) path.push_back(grid.CenterOf(*start_cell));
  for (std::size_t k = 1; k + 1 < cell_path_.size(); ++k) {
    const GridCell in = cell_path_[k] - cell_path_[k - 1];
    const GridCell out = cell_path_[k + 1] - cell_path_[k];
    if (in != out) path.push_back(grid.CenterOf(cell_path_[k]));
  }
  path.push_back(*local_goal);
  return path;
}

}  // namespace pavilion::nav
