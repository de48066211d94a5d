#include "core/features/line_extraction.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <numbers>
#include <numeric>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/features/cluster_cuts.h"
#include "core/features/line_fidelity.h"
#include "core/features/line_fit.h"
#include "core/features/segment_builder.h"
#include "core/math/chi_square.h"

namespace pavilion::core {
namespace {

// Invalid readings in a row that a noisy surface's dropouts may explain (four
// in a row at the simulated dark surface's 30% dropout rate: 0.8%).
constexpr int kMaxDropoutRun = 3;

// Gauss-Newton steps of the range-space fit of a sparse line, and the least
// cos(theta - alpha) of a reading it accepts (incidence within ~0.06 deg of
// grazing: the beam meets the line nowhere near).
constexpr int kRangeFitIterations = 6;
// A sparse line's length (its end rays met by the line) exceeds its readings'
// extent by their noise at most: runs spanning less than the minimum length
// less this are skipped.
constexpr double kSparseSpanMarginM = 0.1;
constexpr double kMinRangeFitCosine = 1e-3;

// NormalQuantile(p), remembered per thread for the last p: every scan of a
// sensor asks for the same consistency_significance.
double CachedNormalQuantile(double p) {
  thread_local double last_p = std::numeric_limits<double>::quiet_NaN();
  thread_local double last_z = 0.0;
  if (p != last_p) {  // exact: a cache, never an approximation
    last_z = NormalQuantile(p);
    last_p = p;
  }
  return last_z;
}

// A segment candidate or cluster: indices into the valid readings (sorted), the
// line re-fitted to them and their weighted residual sum of squares about it
// (the minimum of eqs. 3.4-3.5's objective).
struct Cluster {
  std::vector<int> points;
  Line line;
  double residual_sum = 0.0;
};

// A cluster of `points`, not yet fitted.
Cluster Unfitted(std::vector<int> points) {
  Cluster c;
  c.points = std::move(points);
  return c;
}

// What Agglomerate knows of a pair of clusters.
struct PairState {
  static constexpr char kUnknown = 2;
  double distance = 0.0;   // eq. 3.16, alpha relative to the first cluster's, once measured
  char measured = 0;       // 1: distance is set
  char refused = 0;        // 1: their union is no line (fit consistency, likelihood ratio)
  char shares = kUnknown;  // whether they share points; kUnknown until asked
  int union_index = -1;    // their union, fitted and passing OneLine, in Scratch::unions
};

// Buffers of one extraction, kept per thread so that a scan allocates little.
struct Scratch {
  std::vector<PolarPoint> points;
  std::vector<FitPoint> prepared;
  std::vector<int> reading_index;
  std::vector<WindowFit> windows;
  std::vector<char> usable, inlier;
  std::vector<int> rest;                         // Extractor::OneLine
  std::vector<PairState> pairs;                  // Extractor::Agglomerate
  std::vector<int> slot;                         // Extractor::Agglomerate
  std::vector<Cluster> unions;                   // Extractor::Agglomerate
  std::vector<double> bearings, cosines, sines;  // Extractor::CosSin
  std::vector<char> used;                        // Extractor::AddSparseLines
  PrefixLineFits prefix;                         // Extractor::Run
  std::vector<double> sigmas;  // range sigma per valid reading (adaptive_range_sigma)
};

class Extractor {
 public:
  Extractor(const LaserScan& scan, const LineExtractionOptions& options, Scratch& scratch)
      : scan_(scan),
        options_(options),
        scratch_(scratch),
        points_(scratch.points),
        prepared_(scratch.prepared),
        reading_index_(scratch.reading_index) {
    floor_ << options.alpha_sigma_floor_rad * options.alpha_sigma_floor_rad, 0.0, 0.0,
        options.r_sigma_floor_m * options.r_sigma_floor_m;
    points_.clear();
    prepared_.clear();
    reading_index_.clear();
    const double nominal_weight =
        1.0 / (options.range_sigma_m * options.range_sigma_m);  // eq. 3.11
    points_.reserve(scan.readings.size());
    prepared_.reserve(scan.readings.size());
    reading_index_.reserve(scan.readings.size());
    for (int i = 0; i < static_cast<int>(scan.readings.size()); ++i) {
      const LaserReading& reading = scan.readings[i];
      if (!reading.valid || !std::isfinite(reading.range_m) || !(reading.range_m > 0.0) ||
          !std::isfinite(reading.bearing_rad)) {
        continue;
      }
      const PolarPoint point{reading.range_m, reading.bearing_rad, options.range_sigma_m};
      if (!(options.range_sigma_m > 0.0)) continue;
      const auto [cos_bearing, sin_bearing] = CosSin(i, reading.bearing_rad);
      points_.push_back(point);
      prepared_.push_back({reading.range_m, cos_bearing, sin_bearing, nominal_weight});
      reading_index_.push_back(i);
    }
  }

  // cos and sin of reading i's bearing, cached per thread across scans (in
  // the scratch buffers): a scanner's bearings repeat from scan to scan.
  std::pair<double, double> CosSin(int i, double bearing_rad) {
    std::vector<double>& bearings = scratch_.bearings;
    if (static_cast<int>(bearings.size()) <= i) {
      bearings.resize(i + 1, std::numeric_limits<double>::quiet_NaN());
      scratch_.cosines.resize(i + 1);
      scratch_.sines.resize(i + 1);
    }
    if (bearings[i] != bearing_rad) {  // exact: a cache, never an approximation
      bearings[i] = bearing_rad;
      scratch_.cosines[i] = std::cos(bearing_rad);
      scratch_.sines[i] = std::sin(bearing_rad);
    }
    return {scratch_.cosines[i], scratch_.sines[i]};
  }

  std::vector<Segment> Run() {
    if (options_.adaptive_range_sigma) EstimateNoise();
    scratch_.prefix.Rebuild(prepared_);
    prefix_ = &scratch_.prefix;
    FidelityTest();
    std::vector<Cluster> clusters = SplitInconsistent(Segmentation(), options_.window_size);
    Agglomerate(clusters);
    ResolveSharedPoints(clusters);
    if (options_.sparse_min_points > 0) AddSparseLines(clusters);
    return ToSegments(clusters);
  }

 private:
  // Eqs. 3.4-3.10 over the readings `indices` (ascending), from the prefix
  // moment sums, plus the covariance floor; `residual_sum` as FitMembers.
  std::optional<Line> Fit(std::span<const int> indices, double* residual_sum = nullptr) const {
    std::optional<Line> line = prefix_->FitMembers(indices, residual_sum);
    if (line) line->covariance += floor_;
    return line;
  }

  // Fits `cluster.points`, setting its line and residual sum; false when degenerate.
  bool Refit(Cluster& cluster) const {
    const std::optional<Line> line = Fit(cluster.points, &cluster.residual_sum);
    if (line) cluster.line = *line;
    return line.has_value();
  }

  // §3.2.2: windows of n_f points, model fidelity (3.12) and threshold (3.15);
  // each maximal run of windows with d_i <= d_m gives the union of their points.
  // §3.2.2: the fit of every window of n_f readings and the model fidelity
  // test of every centre (eqs. 3.12-3.15) into scratch_.inlier.
  void FidelityTest() {
    const int n = static_cast<int>(points_.size());
    const int nf = options_.window_size;
    const int h = nf / 2;
    // O(1) per window from prefix moment sums (eqs. 3.4-3.10, line_fit.h).
    const PrefixLineFits& prefix = *prefix_;
    std::vector<WindowFit>& windows = scratch_.windows;
    std::vector<char>& usable = scratch_.usable;
    std::vector<char>& inlier = scratch_.inlier;
    windows.resize(n);
    usable.assign(n, 0);
    inlier.assign(n, 0);
    if (n < nf + 2) return;
    for (int c = h; c + h < n; ++c) {
      // No covariance floor here: a correlated error (§2.2.1.3) is common to
      // neighbouring windows and cancels in their fidelity distance (eq. 3.12);
      // adding it would let windows across corners pass as one line.
      const std::optional<Line> fit =
          prefix.Fit(c - h, c - h + nf, PrefixLineFits::Precision::kFast);
      if (!fit) continue;
      WindowFit& w = windows[c];
      w.alpha_rad = fit->alpha_rad;
      w.r_m = fit->r_m;
      w.covariance = Sym2::Of(fit->covariance);
      if (!(w.covariance.Determinant() > 0.0)) continue;
      w.information = w.covariance.Inverse();  // used by three fidelity distances
      usable[c] = 1;
    }
    for (int c = h + 1; c + h + 1 < n; ++c) {
      if (!usable[c - 1] || !usable[c] || !usable[c + 1]) continue;
      inlier[c] = FidelityPasses(&windows[c - 1], options_.fidelity_threshold);
    }
  }

  // The range noise estimate (adaptive_range_sigma): sets the noisy readings'
  // sigma and weight (eq. 3.11 with the local sigma) and noisy_surfaces_.
  void EstimateNoise() {
    std::vector<double>& sigmas = scratch_.sigmas;
    for (const NoisyRegion& region :
         EstimateRangeSigmas(prepared_, options_.range_sigma_m, options_.range_noise, sigmas)) {
      if (!region.clutter) noisy_surfaces_.push_back(region);
    }
    for (std::size_t k = 0; k < sigmas.size(); ++k) {
      if (sigmas[k] == options_.range_sigma_m) continue;
      points_[k].range_sigma_m = sigmas[k];
      prepared_[k].weight = 1.0 / (sigmas[k] * sigmas[k]);
    }
  }

  // §3.2.2: each maximal run of windows passing the fidelity test gives the
  // union of their readings as a segment candidate.
  std::vector<Cluster> Segmentation() {
    const int n = static_cast<int>(points_.size());
    const int nf = options_.window_size;
    const int h = nf / 2;
    std::vector<Cluster> candidates;
    if (n < nf + 2) return candidates;
    const double gate = ChiSquare2Quantile(options_.significance);
    std::vector<char>& inlier = scratch_.inlier;
    // A noisy surface's readings scatter over the extent of a window (5 cm at
    // 6.6 mm spacing for velvet 0.76 m away): the window fits there are no
    // model points, so its windows take no part, and each region is one
    // candidate for the top-down split of SplitInconsistent, whose residual
    // test has the region's sigma.
    for (const NoisyRegion& region : noisy_surfaces_) {
      std::fill(inlier.begin() + region.first, inlier.begin() + region.last + 1, 0);
    }
    for (int c = 0; c < n;) {
      if (!inlier[c]) {
        ++c;
        continue;
      }
      int last = c;
      while (last + 1 < n && inlier[last + 1]) ++last;
      Cluster cluster;
      cluster.points.resize(last - c + nf);  // readings c - h .. last + h
      std::iota(cluster.points.begin(), cluster.points.end(), c - h);
      if (Refit(cluster)) {
        // Runs parted by fewer than n_f - 1 windows failing the fidelity test
        // (noise, mostly a single window) share readings; when their lines
        // pass eq. 3.16 at alpha and the joined readings the fit consistency
        // test, they are fused here, in scan order, as the overlap level of
        // Agglomerate would fuse them (best pair first) — most of its work
        // done in one pass (the hall's scores unchanged to +-0.001, 3 us per
        // scan saved).
        if (!candidates.empty() && candidates.back().points.back() >= cluster.points.front() &&
            CollinearityDistance(candidates.back().line, cluster.line) <= gate) {
          Cluster joined;
          joined.points.resize(cluster.points.back() - candidates.back().points.front() + 1);
          std::iota(joined.points.begin(), joined.points.end(), candidates.back().points.front());
          if (Refit(joined) && Consistent(joined)) {
            candidates.back() = std::move(joined);
            c = last + 1;
            continue;
          }
        }
        candidates.push_back(std::move(cluster));
      }
      c = last + 1;
    }
    if (noisy_surfaces_.empty()) return candidates;
    // A region is cut where more readings in a row return nothing than a
    // dark surface's dropouts explain (the beam left the surface).
    const auto add_piece = [&](int first, int last) {
      if (last - first + 1 < nf) return;
      Cluster cluster;
      cluster.points.resize(last - first + 1);
      std::iota(cluster.points.begin(), cluster.points.end(), first);
      if (Refit(cluster)) candidates.push_back(std::move(cluster));
    };
    for (const NoisyRegion& region : noisy_surfaces_) {
      int first = region.first;
      for (int i = region.first + 1; i <= region.last; ++i) {
        if (!DropoutGapBefore(i)) continue;
        add_piece(first, i - 1);
        first = i;
      }
      add_piece(first, region.last);
    }
    std::stable_sort(candidates.begin(), candidates.end(), [](const Cluster& a, const Cluster& b) {
      return a.points.front() < b.points.front();
    });
    return candidates;
  }

  // Runs of readings no cluster explains, cut at gaps of invalid readings,
  // split top-down by the fit consistency test into pieces of at least
  // sparse_min_points readings: a face seen at grazing incidence, whose
  // readings lie farther apart than a window can span (5 readings on 1.9 m),
  // is still a line to within the range noise.
  void AddSparseLines(std::vector<Cluster>& clusters) {
    const int n = static_cast<int>(points_.size());
    std::vector<char>& used = scratch_.used;
    used.assign(n, 0);
    for (const Cluster& c : clusters) {
      for (int k : c.points) used[k] = 1;
    }
    // A run spanning less than the minimum length (less the readings' noise
    // at the end rays) cannot give a segment.
    const double sparse_min_span = options_.min_length_m - kSparseSpanMarginM;
    std::vector<Cluster> runs;
    int first = -1;
    for (int k = 0; k <= n; ++k) {
      const bool free = k < n && !used[k];
      const bool gap = free && first >= 0 && DropoutGapBefore(k);
      if (first >= 0 && (!free || gap)) {
        if (k - first >= options_.sparse_min_points && RunSpan(first, k) >= sparse_min_span) {
          Cluster run;
          run.points.resize(k - first);
          std::iota(run.points.begin(), run.points.end(), first);
          if (Refit(run)) runs.push_back(std::move(run));
        }
        first = -1;
      }
      if (free && first < 0) first = k;
    }
    if (runs.empty()) return;
    for (Cluster& c : SplitInconsistent(std::move(runs), options_.sparse_min_points)) {
      // An edge reading at either end (a mixed pixel, the next object) is cut
      // off until the range residuals are consistent.
      while (!RangeConsistent(c)) {
        if (static_cast<int>(c.points.size()) <= options_.sparse_min_points) break;
        const auto range_error = [&](int k) {
          const FitPoint& p = prepared_[k];
          const double cos_u = p.cos_bearing * std::cos(c.line.alpha_rad) +
                               p.sin_bearing * std::sin(c.line.alpha_rad);
          return cos_u > 0.0 ? std::abs(p.range_m - c.line.r_m / cos_u)
                             : std::numeric_limits<double>::infinity();
        };
        if (range_error(c.points.front()) > range_error(c.points.back())) {
          c.points.erase(c.points.begin());
        } else {
          c.points.pop_back();
        }
        if (!Refit(c)) break;
      }
      if (static_cast<int>(c.points.size()) >= options_.sparse_min_points && RangeConsistent(c)) {
        clusters.push_back(std::move(c));
      }
    }
    std::stable_sort(clusters.begin(), clusters.end(), [](const Cluster& a, const Cluster& b) {
      return a.points.front() < b.points.front();
    });
  }

  // Whether more readings in a row returned nothing between valid points k - 1
  // and k (k >= 1) than a dark surface's dropouts explain: the beam left the
  // surface.
  bool DropoutGapBefore(int k) const {
    return reading_index_[k] - reading_index_[k - 1] - 1 > kMaxDropoutRun;
  }

  // The diagonal of the bounding box of points [first, end).
  double RunSpan(int first, int end) const {
    double min_x = std::numeric_limits<double>::infinity(), max_x = -min_x;
    double min_y = min_x, max_y = -min_x;
    for (int k = first; k < end; ++k) {
      const FitPoint& p = prepared_[k];
      const double x = p.range_m * p.cos_bearing;
      const double y = p.range_m * p.sin_bearing;
      min_x = std::min(min_x, x);
      max_x = std::max(max_x, x);
      min_y = std::min(min_y, y);
      max_y = std::max(max_y, y);
    }
    const double dx = max_x - min_x;
    const double dy = max_y - min_y;
    return std::sqrt(dx * dx + dy * dy);
  }

  // The fit consistency test in range: the least sum over lines (alpha, r) of
  // w_i (rho_i - r / cos(theta_i - alpha))^2 — the readings' range errors
  // about the line their beams meet — against the chi^2(n - 2) quantile; a
  // few Gauss-Newton steps from the cluster's fit (eqs. 3.4-3.5 weigh
  // perpendicular distances with the range variance, which at grazing
  // incidence lets a line through two small clusters on different objects,
  // a wall and a visitor in front of it, pass: their readings lie on it, but
  // their beams meet it far from them).
  bool RangeConsistent(const Cluster& c) const {
    double alpha = c.line.alpha_rad;
    double r = c.line.r_m;
    double sum = std::numeric_limits<double>::infinity();
    for (int iteration = 0; iteration < kRangeFitIterations; ++iteration) {
      double h_aa = 0.0, h_ar = 0.0, h_rr = 0.0, g_a = 0.0, g_r = 0.0;
      sum = 0.0;
      const double ca = std::cos(alpha);
      const double sa = std::sin(alpha);
      for (int k : c.points) {
        const FitPoint& p = prepared_[k];
        const double cos_u = p.cos_bearing * ca + p.sin_bearing * sa;  // cos(theta - alpha)
        if (!(cos_u > kMinRangeFitCosine)) return false;               // the beam misses the line
        const double sin_u = p.sin_bearing * ca - p.cos_bearing * sa;
        const double e = p.range_m - r / cos_u;
        const double j_a = r * sin_u / (cos_u * cos_u);  // de/d alpha
        const double j_r = -1.0 / cos_u;                 // de/dr
        sum += p.weight * e * e;
        h_aa += p.weight * j_a * j_a;
        h_ar += p.weight * j_a * j_r;
        h_rr += p.weight * j_r * j_r;
        g_a += p.weight * j_a * e;
        g_r += p.weight * j_r * e;
      }
      if (Consistent(c.points.size(), sum)) return true;
      const double det = h_aa * h_rr - h_ar * h_ar;
      if (!(det > 0.0)) return false;
      alpha -= (h_rr * g_a - h_ar * g_r) / det;
      r -= (h_aa * g_r - h_ar * g_a) / det;
    }
    return Consistent(c.points.size(), sum);
  }

  // The fit consistency test (options: fit_consistency): the residual sum of
  // squares of n independent readings about their fitted line follows
  // chi^2(n - 2).
  bool Consistent(std::size_t n, double residual_sum) const {
    if (!options_.fit_consistency || n <= 2) return true;
    return residual_sum <= ChiSquareQuantileWilsonHilferty(static_cast<int>(n) - 2, consistency_z_);
  }
  bool Consistent(const Cluster& c) const { return Consistent(c.points.size(), c.residual_sum); }

  // Candidates failing the fit consistency test are cut where the two fitted
  // lines leave the smallest residual sum, recursively; pieces with fewer than
  // min_piece readings are dropped (n_f for the window candidates: the minimal
  // segment, §3.2.2; sparse_min_points for sparse lines). An outlier at an end
  // (a mixed pixel) is cut off alone; a bend splits at its vertex. For window
  // candidates the result is in scan order with strictly increasing first
  // readings (they overlap by at most n_f - 1 readings, and every piece has
  // n_f or more).
  std::vector<Cluster> SplitInconsistent(std::vector<Cluster> candidates, int min_piece) {
    std::vector<Cluster> result;
    result.reserve(candidates.size());
    std::vector<Cluster> pending;
    for (auto it = candidates.rbegin(); it != candidates.rend(); ++it) {
      pending.push_back(std::move(*it));
    }
    while (!pending.empty()) {
      Cluster c = std::move(pending.back());
      pending.pop_back();
      if (Consistent(c)) {
        result.push_back(std::move(c));
        continue;
      }
      const int cut = BestTwoLineCut(prepared_, c.points);
      // Right piece first on the stack bottom: pieces come out in scan order.
      Cluster parts[2] = {Unfitted({c.points.begin(), c.points.begin() + cut}),
                          Unfitted({c.points.begin() + cut, c.points.end()})};
      for (int side : {1, 0}) {
        if (static_cast<int>(parts[side].points.size()) < min_piece) continue;
        if (Refit(parts[side])) pending.push_back(std::move(parts[side]));
      }
    }
    return result;
  }

  static std::vector<int> Union(const Cluster& a, const Cluster& b) {
    std::vector<int> joined;
    joined.reserve(a.points.size() + b.points.size());
    std::set_union(a.points.begin(), a.points.end(), b.points.begin(), b.points.end(),
                   std::back_inserter(joined));
    return joined;
  }

  // §3.2.3: agglomerative clustering with the chi^2 test on eq. 3.16. Among the
  // pairs passing the test, overlapping neighbours are fused first, then
  // neighbours, then any collinear pair; within a level the nearest pair goes
  // first. Fusion re-fits the joined points. Clusters stay in scan order (by
  // first point) by construction: the fusion of positions i < j takes position
  // i and keeps its first point, and first points are distinct (see
  // SplitInconsistent), so "neighbours" are consecutive clusters. A cluster
  // changes only when it is fused, so what is known of a pair is kept in a
  // table by slot (a cluster's input position, taken over by the fusion it is
  // first in) and renewed for the fused cluster's pairs only.
  void Agglomerate(std::vector<Cluster>& clusters) {
    const double gate = ChiSquare2Quantile(options_.significance);
    stride_ = static_cast<int>(clusters.size());
    scratch_.pairs.assign(stride_ * stride_, PairState{});
    scratch_.unions.clear();
    std::vector<int>& slot = scratch_.slot;
    slot.resize(stride_);
    std::iota(slot.begin(), slot.end(), 0);
    while (clusters.size() > 1) {
      const int m = static_cast<int>(clusters.size());
      Fusion f = NextFusion(clusters, gate);
      if (f.i < 0) return;
      if (!f.fused) {
        f.fused = Unfitted(Union(clusters[f.i], clusters[f.j]));
        if (!Refit(*f.fused)) return;  // cannot happen for two non-degenerate sets; stop merging
        if (!Consistent(*f.fused)) {
          Pair(f.i, f.j).refused = 1;
          continue;
        }
      }
      clusters[f.i] = std::move(*f.fused);
      clusters.erase(clusters.begin() + f.j);
      slot.erase(slot.begin() + f.j);
      // The fused cluster's pairs are new.
      for (int q = 0; q + 1 < m; ++q) {
        if (q != f.i) Pair(std::min(q, f.i), std::max(q, f.i)) = PairState{};
      }
    }
  }

  enum class Level { kOverlap, kAdjacency, kCollinearity };

  // The pair Agglomerate fuses next: positions i < j (i < 0: none) and their
  // union when it was already fitted.
  struct Fusion {
    int i = -1;
    int j = -1;
    std::optional<Cluster> fused;
  };

  // Agglomerate's pair table entry of positions i < j (slots increase with positions).
  PairState& Pair(int i, int j) const {
    const std::vector<int>& slot = scratch_.slot;
    return scratch_.pairs[slot[i] * stride_ + slot[j]];
  }

  // Eq. 3.16 for positions i < j, measured when first needed: the
  // collinearity level, which needs all pairs, is mostly reached when few
  // clusters are left.
  double Distance(const std::vector<Cluster>& clusters, int i, int j) const {
    PairState& ij = Pair(i, j);
    if (!ij.measured) {
      ij.distance = CollinearityDistance(clusters[i].line, clusters[j].line);
      ij.measured = 1;
    }
    return ij.distance;
  }

  bool Share(const std::vector<Cluster>& clusters, int i, int j) const {
    char& s = Pair(i, j).shares;
    if (s == PairState::kUnknown) s = SharePoints(clusters[i].points, clusters[j].points);
    return s != 0;
  }

  // The level's nearest pair passing eq. 3.16 (neighbours only below the
  // collinearity level); false when there is none.
  bool NearestCollinearPair(const std::vector<Cluster>& clusters, Level level, double gate,
                            Fusion* f) const {
    const int m = static_cast<int>(clusters.size());
    double best_d = gate;
    for (int i = 0; i < m; ++i) {
      for (int j = i + 1; j < m; ++j) {
        if (level != Level::kCollinearity && j != i + 1) break;
        const double d = Distance(clusters, i, j);
        if (d > best_d || Pair(i, j).refused) continue;
        if (level == Level::kOverlap && !Share(clusters, i, j)) continue;
        best_d = d;
        f->i = i;
        f->j = j;
      }
    }
    return f->i >= 0;
  }

  // Overlapping and adjacent fragments of one wall estimate their lines from
  // shared or neighbouring readings: eq. 3.16, which assumes two independent
  // estimates, rejects fragments a noisy reading biased (short ones, whose
  // alpha and r are strongly correlated). For them the readings decide, by the
  // likelihood-ratio test of one line against two (OneLine). Of the
  // neighbouring pairs passing it (and the fit consistency test) the one
  // nearest by eq. 3.16 is fused; false when there is none. A union that
  // passed is kept until its pair is fused or renewed: the test depends on the
  // two clusters only.
  bool NearestOneLinePair(const std::vector<Cluster>& clusters, Level level, double gate,
                          Fusion* f) const {
    std::vector<Cluster>& unions = scratch_.unions;
    const int m = static_cast<int>(clusters.size());
    double best_union_d = std::numeric_limits<double>::infinity();
    int best_union = -1;
    for (int i = 0; i + 1 < m; ++i) {
      const int j = i + 1;
      PairState& ij = Pair(i, j);
      if (ij.refused) continue;
      if (level == Level::kOverlap && !Share(clusters, i, j)) continue;
      const double d = Distance(clusters, i, j);
      if (d >= best_union_d) continue;
      if (ij.union_index < 0) {
        Cluster candidate = Unfitted(Union(clusters[i], clusters[j]));
        if (!OneLine(clusters[i], &candidate, gate)) {
          ij.refused = 1;
          continue;
        }
        ij.union_index = static_cast<int>(unions.size());
        unions.push_back(std::move(candidate));
      }
      best_union_d = d;
      f->i = i;
      f->j = j;
      best_union = ij.union_index;
    }
    if (f->i < 0) return false;
    f->fused = std::move(unions[best_union]);
    return true;
  }

  // The next fusion: by level, the nearest pair passing eq. 3.16, else (below
  // the collinearity level, with the fit consistency test on) the nearest
  // neighbours passing the likelihood-ratio test.
  Fusion NextFusion(const std::vector<Cluster>& clusters, double gate) const {
    Fusion f;
    for (Level level : {Level::kOverlap, Level::kAdjacency, Level::kCollinearity}) {
      if (NearestCollinearPair(clusters, level, gate, &f)) break;
      if (level == Level::kCollinearity || !options_.fit_consistency) continue;
      if (NearestOneLinePair(clusters, level, gate, &f)) break;
    }
    return f;
  }

  // The likelihood-ratio test of Agglomerate for `a` and the union `joined`
  // (points set, fitted here when it passes): the residual sum about the joint
  // line minus those of a's readings and of the rest about their own lines is
  // at most the chi^2(2) quantile `gate`, and the union passes the fit
  // consistency test.
  bool OneLine(const Cluster& a, Cluster* joined, double gate) const {
    double joined_residual = 0.0;
    const std::optional<Line> line = Fit(joined->points, &joined_residual);
    if (!line || !Consistent(joined->points.size(), joined_residual)) return false;
    std::vector<int>& rest = scratch_.rest;
    rest.clear();
    std::set_difference(joined->points.begin(), joined->points.end(), a.points.begin(),
                        a.points.end(), std::back_inserter(rest));
    double separate = a.residual_sum;
    if (rest.size() >= 2) {
      double rest_residual = 0.0;
      if (!Fit(rest, &rest_residual)) return false;
      separate += rest_residual;
    }
    if (joined_residual - separate > gate) return false;
    joined->line = *line;
    joined->residual_sum = joined_residual;
    return true;
  }

  // Non-collinear clusters may still share the readings of their window unions
  // (the fused clusters were not collinear at level alpha). A cluster lying
  // within the span of the other (a fragment between two noise-induced breaks of
  // the fidelity run) gives up its shared readings; clusters overlapping at
  // their ends (a corner) split the shared readings at the single cut that
  // minimizes the squared perpendicular residuals to the two lines. Clusters
  // left with fewer than n_f readings, the minimal segment size (§3.2.2), are
  // dropped.
  void ResolveSharedPoints(std::vector<Cluster>& clusters) const {
    for (std::size_t i = 0; i < clusters.size(); ++i) {
      for (std::size_t j = 0; j < clusters.size(); ++j) {
        if (i == j || clusters[i].points.empty() || clusters[j].points.empty()) continue;
        Cluster& a = clusters[i];
        Cluster& b = clusters[j];
        if (a.points.front() > b.points.front() || !SharePoints(a.points, b.points)) continue;
        std::vector<int> shared;
        std::set_intersection(a.points.begin(), a.points.end(), b.points.begin(), b.points.end(),
                              std::back_inserter(shared));
        if (b.points.back() <= a.points.back()) {
          RemovePoints(b, shared);  // b nested in a's span
          continue;
        }
        if (a.points.front() == b.points.front()) {
          RemovePoints(a, shared);  // a nested in b's span
          continue;
        }
        // a ends where b begins: shared[0, cut) stay with a, the rest go to b.
        const int best_cut = CornerCut(prepared_, shared, a.line, b.line);
        RemovePoints(a, std::span<const int>(shared).subspan(best_cut));
        RemovePoints(b, std::span<const int>(shared).first(best_cut));
      }
    }
    const std::size_t min_points = static_cast<std::size_t>(options_.window_size);
    std::erase_if(clusters, [&](const Cluster& c) { return c.points.size() < min_points; });
  }

  void RemovePoints(Cluster& cluster, std::span<const int> removed) const {
    if (removed.empty()) return;
    std::vector<int> kept;
    kept.reserve(cluster.points.size());
    std::set_difference(cluster.points.begin(), cluster.points.end(), removed.begin(),
                        removed.end(), std::back_inserter(kept));
    cluster.points = std::move(kept);
    if (cluster.points.size() < static_cast<std::size_t>(options_.window_size)) {
      cluster.points.clear();
      return;
    }
    if (!Refit(cluster)) cluster.points.clear();
  }

  std::vector<Segment> ToSegments(const std::vector<Cluster>& clusters) const {
    const double bearing_sigma = EndpointBearingSigma(scan_, options_.endpoint_bearing_sigma_rad);
    const SegmentFilter filter{options_.min_points, options_.min_length_m};
    const SegmentFilter piece_filter{options_.min_points, 0.0};
    std::vector<Segment> segments;
    int line_id = 0;
    std::vector<std::span<const int>> pieces;
    const double max_alpha_variance = options_.max_alpha_sigma_rad * options_.max_alpha_sigma_rad;
    for (const Cluster& c : clusters) {
      if (!(c.line.covariance(0, 0) <= max_alpha_variance)) continue;
      if (!(c.line.covariance(1, 1) <= options_.max_r_sigma_m * options_.max_r_sigma_m)) continue;
      std::optional<Segment> whole =
          BuildSegment(c.line, c.points, points_, reading_index_, bearing_sigma, filter);
      if (!whole) continue;
      // Pieces: runs of members not interrupted by min_gap_readings or more
      // valid readings of something else.
      pieces.clear();
      std::size_t begin = 0;
      for (std::size_t k = 1; k <= c.points.size(); ++k) {
        if (k < c.points.size() && c.points[k] - c.points[k - 1] - 1 < options_.min_gap_readings) {
          continue;
        }
        pieces.emplace_back(c.points.data() + begin, k - begin);
        begin = k;
      }
      if (pieces.size() == 1) {
        whole->line_id = line_id++;
        segments.push_back(*whole);
        continue;
      }
      bool any = false;
      for (std::span<const int> piece : pieces) {
        if (auto s =
                BuildSegment(c.line, piece, points_, reading_index_, bearing_sigma, piece_filter)) {
          s->line_id = line_id;
          segments.push_back(*s);
          any = true;
        }
      }
      if (any) ++line_id;
    }
    return segments;
  }

  const LaserScan& scan_;
  const LineExtractionOptions& options_;
  Scratch& scratch_;
  // Normal quantile at consistency_significance (Wilson-Hilferty, per fit).
  double consistency_z_ = CachedNormalQuantile(options_.consistency_significance);
  Eigen::Matrix2d floor_;
  std::vector<PolarPoint>& points_;
  std::vector<FitPoint>& prepared_;  // points_ prepared for fits (no trigonometry per fit)
  std::vector<int>& reading_index_;
  PrefixLineFits* prefix_ = nullptr;  // moment sums of prepared_, for every fit (in scratch_)
  // Regions of readings whose range sigma was estimated from their scatter
  // (adaptive_range_sigma), in scan order.
  std::vector<NoisyRegion> noisy_surfaces_;
  int stride_ = 0;  // Agglomerate: clusters at its start, the pair table's row length
};

}  // namespace

std::vector<Segment> ExtractLines(const LaserScan& scan, const LineExtractionOptions& options) {
  options.Validate();
  thread_local Scratch scratch;
  return Extractor(scan, options, scratch).Run();
}

}  // namespace pavilion::core
