#pragma once

// The interpretation tree of global localization (thesis §5.4, Figs. 5.11-5.12):
// depth-first, backtracking search for the supporting sets that satisfy the
// geometric constraints at significance alpha, one level per local feature,
// one branch per map feature plus the star branch (an outlier). One search
// with two modes, as §5.5 suggests: hypothesis generation (Algorithm 1,
// identifying while locating: location independent constraints until a
// location is available, then the location dependent ones, re-estimating the
// location with every pairing) and hypothesis tracking (Algorithm 2: location
// dependent constraints at a fixed predicted location).
//
// Bounded cost: the tree nodes visited per search and the hypotheses returned
// are limited by counts, and limit hits are reported.

#include <vector>

#include "core/localization/global/location_estimate.h"
#include "core/localization/global/location_hypothesis.h"
#include "core/localization/map_cross_covariance.h"
#include "core/localization/measurement_prediction.h"

namespace pavilion::core {

struct InterpretationTreeOptions {
  // alpha of every constraint test (§5.4.1: "the only parameter the user has
  // to specify"); the thesis' experiments use 0.95; in (0, 1).
  double significance = 0.95;
  bool use_extension_constraint = true;  // §5.3.2.3
  // Which interpretations count as hypotheses. With the star branch the
  // all-star interpretation always survives (§5.7.1 nonetheless reaches zero
  // hypotheses), so a generated hypothesis needs at least `min_pairings`
  // non-star pairings (p' of Fig. 5.21; 3: two lines fix a location, the
  // third confirms it) and at least p'_best - `pairing_margin`: an
  // interpretation that leaves several features unexplained where another
  // explains them all is no rival. >= 1 and >= 0.
  int min_pairings = 3;
  int pairing_margin = 1;
  // Bounded cost: tree nodes (pairing tests) per search, hypotheses returned;
  // >= 1. Chosen: a truncated search may miss the true hypothesis, and a lone
  // wrong survivor is then localized. The hall's 12-feature local maps stay
  // below 20,000 nodes; the office floor's 200-feature map needed a median
  // 34,000 and at most 924,000 over 80 generations (~0.2 us a node: 165 ms).
  long max_tree_nodes = 1000000;
  int max_hypotheses = 64;
  LocationEstimateOptions location;

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct TreeSearchStats {
  long nodes = 0;   // pairing tests
  long leaves = 0;  // complete interpretations reached
  bool node_limit_hit = false;
  bool hypothesis_limit_hit = false;
};

// Holds a reference to the predictor (and through it the map).
class InterpretationTree {
 public:
  InterpretationTree(const MeasurementPredictor& predictor,
                     const InterpretationTreeOptions& options = {});

  // Algorithm 1 without a prior location: the hypotheses of `local`, best
  // first (§5.5.2), with available locations, duplicates (eq. 5.70 below
  // chi^2_{alpha,3}) removed. Observations are taken longest line first, then
  // the longest line off parallel to the first (so that a location is
  // available early, §5.4.1), then by length, points last: the order only
  // affects speed.
  std::vector<LocationHypothesisData> Generate(const LocalMap& local, TreeSearchStats* stats) const;

  // Algorithm 2 at `predicted` (not re-estimated): every supporting set
  // whose pairings pass the unary, visibility, rigidity and extension tests
  // there. Returned with `predicted` as location; only interpretations that
  // pair every local feature that has a candidate (the star branch is kept
  // for those without one; joint incompatibility is resolved when the
  // offspring is estimated, HypothesisTracker).
  std::vector<LocationHypothesisData> Track(const LocalMap& local,
                                            const PoseWithCovariance& predicted,
                                            const PoseMapCrossCovariance* correlations,
                                            TreeSearchStats* stats) const;

  // The location dependent constraints of one pairing at `location`, in the
  // order visibility - rigidity - extension (§5.4.1).
  bool SatisfiesLocationDependent(const LocalFeature& local, MapFeatureRef feature,
                                  const PoseWithCovariance& location,
                                  const PoseMapCrossCovariance* correlations = nullptr) const;

  const InterpretationTreeOptions& options() const { return options_; }
  const GlobalMapFeatures& global() const { return global_; }
  double gate(int dof) const { return gates_[dof]; }  // chi^2_{alpha,dof}, dof 1..3

 private:
  struct Node;
  struct Search;
  static Node RootNode(const LocalMap& local);
  std::vector<int> ObservationOrder(const LocalMap& local) const;
  std::vector<std::vector<int>> Candidates(const LocalMap& local) const;  // unary-compatible
  void GenerateNode(Search* search, int level, const Node& h) const;
  bool Extend(Search* search, const Node& h, int local, int global, Node* child) const;
  void TrackNode(Search* search, int level, const Node& h) const;
  std::vector<LocationHypothesisData> Finish(Search* search) const;

  const MeasurementPredictor& predictor_;
  InterpretationTreeOptions options_;
  GlobalMapFeatures global_;
  double gates_[4] = {0.0, 0.0, 0.0, 0.0};
};

}  // namespace pavilion::core
