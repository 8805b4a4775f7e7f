#pragma once
// ACMH multi-hypothesis joint view selection (docs/algorithm.md §3): from the per-view costs of
// the 8 propagated candidates, each source view gets a probability of being a good view;
// 15 Monte-Carlo draws turn the probabilities into integer view weights.
#include <math.h>

#include "kernels/propagation_pattern.h"
#include "kernels/random.h"

namespace mpmvs {
namespace kernels {

struct ViewSelectionParams {
  float good_threshold = 0.8f;  // tau(t), see GoodMatchThreshold
  float bad_threshold = 1.2f;
  float good_weight_beta = 0.18f;   // exp(-c^2 / 0.18), i.e. beta = 0.3
  float fallback_beta = 0.32f;      // exp(-tau^2 / 0.32)
  int num_samples = 15;
  float neighbour_selected = 0.9f;  // prior from a neighbour that selected the view
  float neighbour_unselected = 0.1f;
};

// tau(t) = tau0 * exp(-t^2 / alpha), t restarting at 0 at every window scale.
MPMVS_HD MPMVS_FORCE_INLINE float GoodMatchThreshold(int t, float tau0 = 0.8f, float alpha = 90.f) {
  return tau0 * expf(-static_cast<float>(t * t) / alpha);
}

// costs[k * num_views + s]: cost of candidate k in view s; candidate_valid[k]: whether the
// region produced a candidate (invalid ones are left out of the statistics). prior[s]:
// neighbour prior. Writes weights[s] (number of draws) and returns the selected-view mask.
MPMVS_HD inline uint32_t SelectViews(const float* costs, const bool* candidate_valid,
                                     int num_views, const float* prior,
                                     const ViewSelectionParams& params, RandomStream* rng,
                                     float* weights) {
  float prob[kMaxSourceViews];
  float total = 0.f;
  const float tau = params.good_threshold;
  for (int s = 0; s < num_views; ++s) {
    // A view without prior (one not costed, with costed_views) gets probability 0 whatever
    // its costs: its statistics need not be gathered.
    if (prior[s] == 0.f) {
      prob[s] = 0.f;
      continue;
    }
    int n_good = 0, n_bad = 0;
    float good_sum = 0.f;
    for (int k = 0; k < kNumRegions; ++k) {
      if (!candidate_valid[k]) continue;
      const float c = costs[k * num_views + s];
      if (c < tau) {
        ++n_good;
        good_sum += ExpNeg(c * c / params.good_weight_beta);
      } else if (c > params.bad_threshold) {
        ++n_bad;
      }
    }
    float p = 0.f;
    if (n_good > 2 && n_bad < 3) {
      p = prior[s] * good_sum / n_good;
    } else if (n_bad < 3) {
      p = prior[s] * expf(-tau * tau / params.fallback_beta);
    }
    prob[s] = p;
    total += p;
  }
  if (!(total > 0.f)) {
    // Every view looks bad for every candidate: fall back to the views that matched at all
    // (uniform), else to all views, rather than dividing by zero.
    for (int s = 0; s < num_views; ++s) {
      float best = kInvalidCost;
      for (int k = 0; k < kNumRegions; ++k) {
        if (candidate_valid[k]) best = Min(best, costs[k * num_views + s]);
      }
      prob[s] = best < kInvalidCost ? 1.f : 0.f;
      total += prob[s];
    }
    if (!(total > 0.f)) {  // uniform over the views with a prior (those costed)
      for (int s = 0; s < num_views; ++s) {
        prob[s] = prior[s] > 0.f ? 1.f : 0.f;
        total += prob[s];
      }
    }
  }
  // A single view with any probability takes every draw (each draw r lies in [0, total),
  // and the views before it sum to 0, it to total): its weight is known without drawing.
  // Always the case with one source view, as in two-view pairs.
  int only = -1, num_positive = 0;
  for (int s = 0; s < num_views; ++s) {
    if (prob[s] > 0.f) {
      only = s;
      ++num_positive;
    } else if (!(prob[s] == 0.f)) {
      num_positive = 2;  // NaN: leave it to the draws
    }
  }
  if (num_positive == 1 && params.num_samples > 0) {
    for (int s = 0; s < num_views; ++s) weights[s] = 0.f;
    weights[only] = static_cast<float>(params.num_samples);
    rng->Skip(static_cast<uint32_t>(params.num_samples));
    return 1u << only;
  }
  // Roulette draws. The chosen view is the first whose cumulative probability exceeds the
  // draw, i.e. the number of cumulative sums <= it: counted without branches, since the
  // draws are random and a search loop mispredicts most of them.
  float cumulative[kMaxSourceViews];
  float acc = 0.f;
  for (int s = 0; s < num_views; ++s) {
    acc += prob[s];
    cumulative[s] = acc;
    weights[s] = 0.f;
  }
  for (int i = 0; i < params.num_samples; ++i) {
    const float r = rng->Uniform() * total;
    int chosen = 0;
    for (int s = 0; s < num_views; ++s) chosen += cumulative[s] <= r ? 1 : 0;
    chosen = MinI(chosen, num_views - 1);
    // Guard against rounding picking a zero-probability last view.
    while (prob[chosen] <= 0.f && chosen > 0) --chosen;
    weights[chosen] += 1.f;
  }
  uint32_t mask = 0;
  for (int s = 0; s < num_views; ++s) {
    if (weights[s] > 0.f) mask |= (1u << s);
  }
  return mask;
}

// View prior from the selected-view masks of the (up to 4) direct neighbours.
MPMVS_HD inline void NeighbourViewPrior(const uint32_t* neighbour_masks, int num_neighbours,
                                        int num_views, const ViewSelectionParams& params,
                                        float* prior) {
  for (int s = 0; s < num_views; ++s) {
    float p = 0.f;
    for (int i = 0; i < num_neighbours; ++i) {
      p += (neighbour_masks[i] >> s & 1u) ? params.neighbour_selected : params.neighbour_unselected;
    }
    prior[s] = num_neighbours > 0 ? p : 1.f;
  }
}

}  // namespace kernels
}  // namespace mpmvs
