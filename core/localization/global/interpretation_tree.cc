#include "core/localization/global/interpretation_tree.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "core/localization/matching.h"
#include "core/math/chi_square.h"

namespace pavilion::core {
namespace {

// Lines whose directions differ by more than this count as "off parallel" for
// the observation order (§5.4.1's perpendicular rule, relaxed). Speed only.
constexpr double kOffParallelRad = 0.5;

}  // namespace

void InterpretationTreeOptions::Validate() const {
  if (!(significance > 0.0 && significance < 1.0)) {
    throw std::invalid_argument("significance must be in (0, 1)");
  }
  if (min_pairings < 1) throw std::invalid_argument("min_pairings must be >= 1");
  if (pairing_margin < 0) throw std::invalid_argument("pairing_margin must be >= 0");
  if (max_tree_nodes < 1) throw std::invalid_argument("max_tree_nodes must be >= 1");
  if (max_hypotheses < 1) throw std::invalid_argument("max_hypotheses must be >= 1");
  location.Validate();
}

// A tree node: the partial interpretation h of Algorithm 1.
struct InterpretationTree::Node {
  std::vector<Pairing> support;  // one per local feature, star until assigned
  std::vector<int> global;       // per local feature: its pairing's index into global_, -1 star
  int pairings = 0;
  bool available = false;
  LocationEstimate estimate;
};

struct InterpretationTree::Search {
  const LocalMap* local = nullptr;
  std::vector<int> order;
  std::vector<std::vector<int>> candidates;       // per local feature: global indices
  const PoseWithCovariance* predicted = nullptr;  // Track only
  TreeSearchStats* stats = nullptr;
  int best_pairings = 0;
  int margin = 0;
  int min_pairings = 0;
  std::vector<LocationHypothesisData> leaves;

  int Needed() const { return std::max(min_pairings, best_pairings - margin); }
  bool Exhausted(long max_nodes) {
    if (stats->nodes < max_nodes) return false;
    stats->node_limit_hit = true;
    return true;
  }
};

// The root h of the search: every local feature on the star branch, no location.
InterpretationTree::Node InterpretationTree::RootNode(const LocalMap& local) {
  Node root;
  root.support.resize(local.features.size());
  root.global.assign(local.features.size(), -1);
  for (std::size_t i = 0; i < root.support.size(); ++i) root.support[i].local = static_cast<int>(i);
  return root;
}

InterpretationTree::InterpretationTree(const MeasurementPredictor& predictor,
                                       const InterpretationTreeOptions& options)
    : predictor_(predictor), options_(options), global_(MakeGlobalMapFeatures(predictor.map())) {
  options_.Validate();
  for (int dof = 1; dof <= 3; ++dof) gates_[dof] = ChiSquareQuantile(options_.significance, dof);
}

std::vector<int> InterpretationTree::ObservationOrder(const LocalMap& local) const {
  std::vector<int> order(local.features.size());
  std::iota(order.begin(), order.end(), 0);
  auto length = [&](int i) {
    return local.features[static_cast<std::size_t>(i)].geometry.length_m;
  };
  auto is_line = [&](int i) {
    return local.features[static_cast<std::size_t>(i)].geometry.is_line;
  };
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (is_line(a) != is_line(b)) return is_line(a);
    return length(a) > length(b);
  });
  if (order.size() >= 3 &&
      is_line(order[0])) {  // the longest line off parallel to the first second
    const double first = local.features[static_cast<std::size_t>(order[0])].geometry.line.alpha_rad;
    for (std::size_t k = 1; k < order.size() && is_line(order[k]); ++k) {
      const double a = local.features[static_cast<std::size_t>(order[k])].geometry.line.alpha_rad;
      const double d = std::abs(std::sin(a - first));
      if (d > std::sin(kOffParallelRad)) {
        std::rotate(order.begin() + 1, order.begin() + static_cast<long>(k),
                    order.begin() + static_cast<long>(k) + 1);
        break;
      }
    }
  }
  return order;
}

std::vector<std::vector<int>> InterpretationTree::Candidates(const LocalMap& local) const {
  std::vector<std::vector<int>> candidates(local.features.size());
  for (std::size_t l = 0; l < local.features.size(); ++l) {
    const LocalFeature& f = local.features[l];
    for (std::size_t g = 0; g < global_.refs.size(); ++g) {
      if (!CanPair(f.observation.type, global_.refs[g].type)) continue;
      if (!SatisfiesUnaryConstraint(f.geometry, global_.geometry[g], gates_[1])) continue;
      candidates[l].push_back(static_cast<int>(g));
    }
  }
  return candidates;
}

bool InterpretationTree::SatisfiesLocationDependent(
    const LocalFeature& local, MapFeatureRef feature, const PoseWithCovariance& location,
    const PoseMapCrossCovariance* correlations) const {
  const PredictedMeasurement prediction =
      predictor_.Predict(feature, local.observation.type, location, local.view, correlations);
  if (!predictor_.IsVisible(prediction, location, local.view)) return false;  // Table 5.3
  const Innovation innovation = ComputeInnovation(prediction, local.observation);
  if (!(innovation.nis <= gates_[innovation.dimension])) return false;  // rigidity, §5.3.2.1
  return !options_.use_extension_constraint ||
         predictor_.SatisfiesExtensionConstraint(feature, local.observation.segments, location,
                                                 local.view);  // Table 5.4
}

// Part A and part B of Algorithm 1 for the pairing {l, g} under `h`.
bool InterpretationTree::Extend(Search* search, const Node& h, int local, int global,
                                Node* child) const {
  const LocalFeature& l = search->local->features[static_cast<std::size_t>(local)];
  const MapFeatureRef ref = global_.refs[static_cast<std::size_t>(global)];
  if (h.available) {  // part A: location dependent constraints at L_h
    if (!SatisfiesLocationDependent(l, ref, h.estimate.location)) return false;
  } else {  // part B: binary constraints with every pairing so far
    for (const Pairing& q : h.support) {
      if (q.star) continue;
      const auto qg = static_cast<std::size_t>(h.global[static_cast<std::size_t>(q.local)]);
      if (!SatisfiesBinaryConstraint(
              l.geometry, search->local->features[static_cast<std::size_t>(q.local)].geometry,
              global_.geometry[static_cast<std::size_t>(global)], global_.geometry[qg],
              gates_[1])) {
        return false;
      }
    }
  }
  *child = h;
  child->support[static_cast<std::size_t>(local)] = Pairing{local, ref, false};
  child->global[static_cast<std::size_t>(local)] = global;
  ++child->pairings;
  child->estimate = EstimateLocation(predictor_, *search->local, child->support, options_.location);
  const bool was_available = h.available;
  child->available = child->estimate.available;
  if (was_available || !child->available) return was_available ? child->available : true;
  for (const Pairing& q : child->support) {  // the location just became available
    if (q.star) continue;
    if (!SatisfiesLocationDependent(search->local->features[static_cast<std::size_t>(q.local)],
                                    q.feature, child->estimate.location)) {
      return false;
    }
  }
  return true;
}

void InterpretationTree::GenerateNode(Search* search, int level, const Node& h) const {
  const int count = static_cast<int>(search->order.size());
  if (h.pairings + (count - level) < search->Needed()) return;  // cannot reach p'_min
  if (level == count) {
    ++search->stats->leaves;
    if (!h.available) return;  // no unique location: not a hypothesis (§5.4.2)
    search->leaves.push_back(LocationHypothesisData{h.estimate.location, h.support, h.pairings,
                                                    h.estimate.joint_mahalanobis});
    search->best_pairings = std::max(search->best_pairings, h.pairings);
    return;
  }
  const int l = search->order[static_cast<std::size_t>(level)];
  Node child;
  for (const int g : search->candidates[static_cast<std::size_t>(l)]) {
    if (search->Exhausted(options_.max_tree_nodes)) return;
    ++search->stats->nodes;
    if (Extend(search, h, l, g, &child)) GenerateNode(search, level + 1, child);
  }
  GenerateNode(search, level + 1, h);  // the star branch
}

std::vector<LocationHypothesisData> InterpretationTree::Generate(const LocalMap& local,
                                                                 TreeSearchStats* stats) const {
  Search search;
  search.local = &local;
  search.order = ObservationOrder(local);
  search.candidates = Candidates(local);
  search.stats = stats;
  search.margin = options_.pairing_margin;
  search.min_pairings = options_.min_pairings;
  const Node root = RootNode(local);
  GenerateNode(&search, 0, root);
  return Finish(&search);
}

void InterpretationTree::TrackNode(Search* search, int level, const Node& h) const {
  const int count = static_cast<int>(search->order.size());
  if (h.pairings + (count - level) < search->best_pairings) return;  // a maximal set only
  if (level == count) {
    ++search->stats->leaves;
    search->leaves.push_back(
        LocationHypothesisData{*search->predicted, h.support, h.pairings, 0.0});
    search->best_pairings = std::max(search->best_pairings, h.pairings);
    return;
  }
  const int l = search->order[static_cast<std::size_t>(level)];
  for (const int g : search->candidates[static_cast<std::size_t>(l)]) {
    if (search->Exhausted(options_.max_tree_nodes)) return;
    if (static_cast<long>(search->leaves.size()) >= options_.max_hypotheses) {
      search->stats->hypothesis_limit_hit = true;
      return;
    }
    Node child = h;
    child.support[static_cast<std::size_t>(l)] =
        Pairing{l, global_.refs[static_cast<std::size_t>(g)], false};
    ++child.pairings;
    TrackNode(search, level + 1, child);
  }
  TrackNode(search, level + 1, h);  // the star branch
}

std::vector<LocationHypothesisData> InterpretationTree::Track(
    const LocalMap& local, const PoseWithCovariance& predicted,
    const PoseMapCrossCovariance* correlations, TreeSearchStats* stats) const {
  Search search;
  search.local = &local;
  search.order = ObservationOrder(local);
  search.predicted = &predicted;
  search.stats = stats;
  // The location is fixed: each pairing's tests are independent of the others.
  const std::vector<std::vector<int>> unary = Candidates(local);
  search.candidates.resize(unary.size());
  for (std::size_t l = 0; l < unary.size(); ++l) {
    for (const int g : unary[l]) {
      ++stats->nodes;
      if (SatisfiesLocationDependent(local.features[l], global_.refs[static_cast<std::size_t>(g)],
                                     predicted, correlations)) {
        search.candidates[l].push_back(g);
      }
    }
  }
  const Node root = RootNode(local);
  TrackNode(&search, 0, root);
  std::vector<LocationHypothesisData> out;
  for (LocationHypothesisData& h : search.leaves) {
    if (h.pairings >= search.best_pairings) out.push_back(std::move(h));
  }
  return out;
}

// Best first; p' at least Needed(); duplicates (eq. 5.70) and the excess dropped.
std::vector<LocationHypothesisData> InterpretationTree::Finish(Search* search) const {
  std::vector<LocationHypothesisData>& leaves = search->leaves;
  std::stable_sort(leaves.begin(), leaves.end(), BetterHypothesis);
  std::vector<LocationHypothesisData> out;
  for (LocationHypothesisData& h : leaves) {
    if (h.pairings < search->Needed()) break;
    const bool duplicate = std::any_of(out.begin(), out.end(), [&](const auto& kept) {
      return HypothesisDistance(kept.location, h.location) < gates_[3];
    });
    if (duplicate) continue;
    if (static_cast<long>(out.size()) >= options_.max_hypotheses) {
      search->stats->hypothesis_limit_hit = true;
      break;
    }
    out.push_back(std::move(h));
  }
  return out;
}

}  // namespace pavilion::core
