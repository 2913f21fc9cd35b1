// HyDICE (seed 002 Sect. 3, Alg. 1-3): discrete search over a region decomposition
// (core/model/decomposition.hpp) computes leads that guide a sampling-based motion planner.
// The pieces below are exposed for the tests.
#pragma once
#include <bit>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "core/model/decomposition.hpp"
#include "core/run/method_entry.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

// Normalization exponents of the region weights (Sect. 3.2.3, 3.3.1). No defaults here: the
// method's declared options (hydice.cpp, exponent_options) are the one source of them.
struct HydiceExponents {
  double nu, zeta, tau;
};

// w_i(q) = vol^ν cov^ζ / t^τ (lead weight, Sect. 3.2.3).
double hydice_lead_weight(const HydiceExponents& e, double vol, double cov, double t);
// w_sel(D_i(q)) = vol^ν / (t^τ cov^ζ) (region selection, Sect. 3.3.1).
double hydice_selection_weight(const HydiceExponents& e, double vol, double cov, double t);

// A lead: the regions of a path v_safe -> ... -> v_unsafe in G_D (v_safe's edges go to
// `starts`, v_unsafe's come from every is_unsafe region), start region first. With `weight`
// it is the shortest path for edge cost 1/(w(a) w(b)) (Dijkstra over the implicit graph);
// with `rng` instead (weight empty) every edge gets an independent cost uniform in (0, 1], a
// random path (Sect. 3.2.3). A* with h(r) = heuristic_edge_cost * d.hops_to_unsafe(r) (0: plain
// Dijkstra), expanded regions never reopened: the exact shortest path when that h never
// overestimates, a weighted (greedier) search otherwise; regions with no path to an unsafe one
// (hops = inf) are pruned. Empty when no unsafe
// region is reachable or `max_expanded` regions were expanded without reaching one.
std::vector<RegionId> hydice_lead(const Decomposition& d, std::span<const RegionId> starts,
                                  const std::function<double(RegionId)>& weight, Rng* rng,
                                  double heuristic_edge_cost = 0.0, std::size_t max_expanded = 50'000'000);

// RegionId -> uint32 map for the per-region data of the lead search and the planner. With a
// dense decomposition (Decomposition::dense_size() > 0) a paged flat array indexed by
// dense_index(r): pages of 2^kPageBits indices, allocated when first touched, so that memory
// follows the regions touched rather than |V_D| (67 M regions at navigation 4096²); otherwise
// open addressing on splitmix64(r) with load <= 1/2. clear() is O(1): an entry is live only
// when it carries the stamp of the current generation.
class RegionSlots {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  // Chooses the layout for d's ids and clears; a no-op (beyond clear) when d is the one attached.
  void attach(const Decomposition& d);
  void clear();
  std::uint32_t find(RegionId r) const;  // kNone when absent
  // Hints the cache with r's cell (dense layout only): the lead search touches a region's
  // neighbours one after another, each a likely cache miss, so it requests them all first.
  void prefetch(RegionId r) const {
    if (!dense_) return;
    const std::uint64_t i = dec_->dense_index(r);
    if (const auto& page = pages_[i >> kPageBits]) __builtin_prefetch(&page[i & kPageMask]);
  }
  // The value of r; when r is absent, `value` is inserted for it and `fresh` set.
  std::uint32_t find_or_insert(RegionId r, std::uint32_t value, bool& fresh) {
    if (dense_) {
      const std::uint64_t i = dec_->dense_index(r);
      std::unique_ptr<DenseCell[]>& page = pages_[i >> kPageBits];
      if (!page) page = new_page();
      DenseCell& c = page[i & kPageMask];
      fresh = c.stamp != stamp_;
      if (fresh) c = DenseCell{value, stamp_};
      return c.value;
    }
    return hashed_find_or_insert(r, value, fresh);
  }

 private:
  // 2^12 indices (32 KB) a page: navigation's ids run row-major over the terrains (4 per
  // terrain), so a page is a strip of 1024 terrains, and the page table at 4096² has 16 k entries.
  static constexpr unsigned kPageBits = 12;
  static constexpr std::uint64_t kPageMask = (std::uint64_t{1} << kPageBits) - 1;
  struct DenseCell {
    std::uint32_t value = 0, stamp = 0;
  };
  struct HashSlot {
    RegionId region = 0;
    std::uint32_t value = 0, stamp = 0;
  };
  std::unique_ptr<DenseCell[]> new_page() const;
  std::uint32_t hashed_find_or_insert(RegionId r, std::uint32_t value, bool& fresh);
  void grow();
  const Decomposition* dec_ = nullptr;
  std::uint64_t dense_size_ = 0;
  bool dense_ = false;
  std::vector<std::unique_ptr<DenseCell[]>> pages_;
  std::vector<HashSlot> table_;
  std::size_t live_ = 0;  // live entries of the hash table
  std::uint32_t stamp_ = 1;
};

// The lead search with its workspace kept between leads (the regions touched indexed by a
// RegionSlots, reset in O(1); an indexed 4-ary heap): no allocation per lead once warm.
class LeadSearch {
 public:
  // As hydice_lead.
  std::vector<RegionId> find(const Decomposition& d, std::span<const RegionId> starts,
                             const std::function<double(RegionId)>& weight, Rng* rng, double heuristic_edge_cost = 0.0,
                             std::size_t max_expanded = 50'000'000);
  std::size_t expanded() const { return expanded_; }  // regions expanded by the last find

 private:
  static constexpr std::uint32_t kNoParent = 0xffffffffu;
  static constexpr std::uint32_t kNotQueued = 0xffffffffu;
  struct Entry {
    RegionId region;
    double dist, w, h;
    std::uint32_t parent;
    std::uint32_t h_rank;  // orders h (see OpenItem)
    bool done;
  };
  // A* queue entry, ordered by f = dist + h, ties to the smaller h (the deeper region), then to
  // the older entry, packed into one 128-bit key compared as an integer (the heap's
  // comparisons were its cost): the bits of f (>= 0, so its IEEE bits order as the number),
  // then h's rank, then the entry. h = c x hops with c > 0 the same for every region of a search
  // (or h = 0 when c = 0: rank 0), so hops (a whole number of G_D edges) ranks h.
  struct OpenItem {
    unsigned __int128 key;
    static OpenItem make(double f, std::uint32_t h_rank, std::uint32_t entry) {
      return {(static_cast<unsigned __int128>(std::bit_cast<std::uint64_t>(f)) << 64) |
              (static_cast<unsigned __int128>(h_rank) << 32) | entry};
    }
    std::uint32_t entry() const { return static_cast<std::uint32_t>(key); }
    bool operator>(const OpenItem& o) const { return key > o.key; }
  };
  // The entry of r, created (dist 0, no parent, weight not computed) when new; `fresh` says so.
  std::uint32_t entry_of(RegionId r, bool& fresh) {
    const std::uint32_t k = slots_.find_or_insert(r, static_cast<std::uint32_t>(entries_.size()), fresh);
    if (fresh) {
      entries_.push_back(Entry{r, 0.0, std::numeric_limits<double>::quiet_NaN(), 0.0, kNoParent, 0, false});
      heap_pos_.push_back(kNotQueued);
    }
    return k;
  }
  RegionSlots slots_;
  std::vector<Entry> entries_;
  // The index in open_ of each entry (kNotQueued when not queued), apart from the entries so
  // that the heap's moves write 4 bytes into a dense array rather than into a 40-byte entry.
  std::vector<std::uint32_t> heap_pos_;
  std::vector<OpenItem> open_;
  std::vector<RegionId> nb_;
  std::size_t expanded_ = 0;
};

// D_avail for a lead (Sect. 3.3.1): scanning the lead backwards, each reached region joins
// with probability 1 / (1 + |D_avail|).
std::vector<RegionId> hydice_available(std::span<const RegionId> lead, const std::function<bool(RegionId)>& reached,
                                       Rng& rng);

// Index i drawn with probability proportional to w[i] (w >= 0, some > 0).
std::size_t hydice_pick_weighted(std::span<const double> w, Rng& rng);
// Coverage cell i drawn with probability ∝ 1 / nsel_i^2 (Sect. 3.3.2); nsel counts the
// selections so far plus one, so that never-selected cells have a finite weight.
std::size_t hydice_pick_cell(std::span<const std::uint32_t> selections, Rng& rng);

MethodEntry hydice_method();
MethodEntry hydice_noleads_method();

// This folder's methods, in the order `hyfal list` shows them: the registry's entry
// (hyfal_planner(hydice) in core/planners/CMakeLists.txt).
inline std::vector<MethodEntry> hydice_methods() { return {hydice_method(), hydice_noleads_method()}; }

}  // namespace hyfal
