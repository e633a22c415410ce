#include "methods/zslab/zslab_reuse_plan.hpp"

#include <algorithm>

#include "methods/zslab/zslab_kept.hpp"

namespace imx {

namespace {

// The budget: own arrays by size, the largest evicted first (ties: the later stage). Returns
// the bytes of those kept.
uint64_t fit_budget(const ZslabReuseInput& in, std::vector<bool>& keep) {
  const size_t end = in.capacity.size();
  std::vector<size_t> by_size;
  uint64_t planned = 0;
  for (size_t k = 0; k < end; ++k)
    if (in.capacity[k] > 0) {
      keep[k] = true;
      by_size.push_back(k);
      planned += KeptSlabArrays::bytes_for(in.samples, in.capacity[k]);
    }
  std::stable_sort(by_size.begin(), by_size.end(), [&](size_t a, size_t b) {
    return in.capacity[a] != in.capacity[b] ? in.capacity[a] > in.capacity[b] : a > b;
  });
  for (size_t k : by_size) {
    if (planned <= in.budget) break;
    keep[k] = false;
    planned -= KeptSlabArrays::bytes_for(in.samples, in.capacity[k]);
  }
  return planned;
}

// The kept own array each kept stage reuses: the first of the cache's with its key and shape,
// each used once.
std::vector<int> match_kept(const ZslabReuseInput& in, const std::vector<bool>& keep) {
  const size_t end = in.capacity.size();
  std::vector<int> matched(end, -1);
  std::vector<bool> used(in.kept_own.size(), false);
  for (size_t k = 0; k < end; ++k) {
    if (!keep[k]) continue;
    for (size_t e = 0; e < in.kept_own.size(); ++e) {
      const std::optional<KeptArrayShape>& a = in.kept_own[e];
      if (!used[e] && a && a->key == in.own_key[k] && a->samples == in.samples &&
          a->capacity == in.capacity[k]) {
        matched[k] = static_cast<int>(e);
        used[e] = true;
        break;
      }
    }
  }
  return matched;
}

}  // namespace

int ZslabReusePlan::stages_run() const {
  return static_cast<int>(std::count(render.begin(), render.end(), true));
}

ZslabReusePlan plan_zslab_reuse(const ZslabReuseInput& in) {
  const size_t end = in.capacity.size();
  ZslabReusePlan plan;
  plan.keep.assign(end, false);
  plan.own_bytes = fit_budget(in, plan.keep);
  plan.matched = match_kept(in, plan.keep);

  // The first stage whose object must be rendered, and where the merges start.
  plan.first = end;
  for (size_t k = 0; k < end && plan.first == end; ++k)
    if (plan.matched[k] < 0) plan.first = k;
  const size_t at = in.prefix_stage;
  plan.read_prefix = in.prefix && at >= 1 && at <= plan.first && in.prefix->key == in.chain[at] &&
                     in.prefix->samples == in.samples && in.prefix->capacity == in.layers;
  plan.start = plan.read_prefix ? at : 0;

  // Keep the merged array before the first changed stage, the input of the likeliest next edit,
  // when it saves two merges or more (or all of them), within the budget.
  plan.prefix_bytes = KeptSlabArrays::bytes_for(in.samples, in.layers);
  const bool prefix_fits = plan.own_bytes + plan.prefix_bytes <= in.budget;
  plan.write_prefix =
      plan.first > plan.start && (plan.first >= 2 || plan.first == end) && prefix_fits;
  plan.drop_prefix = !plan.read_prefix || (!plan.write_prefix && !prefix_fits);

  plan.render.assign(end, false);
  for (size_t k = plan.start; k < end; ++k) plan.render[k] = plan.matched[k] < 0;
  return plan;
}

}  // namespace imx
