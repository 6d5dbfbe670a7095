// MemoryBudget: what a bake may hold in memory and what it holds. It owns the limit
// (Settings::max_memory_mb, or half the physical memory when that is 0), the scene's tables as
// last measured and the forecast of the final gather's trace; estimate() adds what the solution
// holds now and over() tells refinement when more links and nodes would pass the limit, so a
// bake stops refining with room left for its output instead of outgrowing the machine.
// It keeps no reference to the solve: the parts it reads come in a MemoryView at each call.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "radiosity/direct_light.h"
#include "radiosity/final_gather.h"
#include "radiosity/gathering.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link_store.h"
#include "radiosity/pockets.h"
#include "radiosity/scene.h"
#include "radiosity/settings.h"
#include "radiosity/visibility.h"

namespace radiosity {

// The parts of a solve the budget reads, as they stand; held for one call only.
struct MemoryView {
    const Settings& settings;        // rays per link, gather rays
    const SceneDesc& scene;          // the objects' arrays, which are output and their corners
    const Hierarchy& h;              // nodes, tables, and the leaves under the output points
    const LinkStore& links;
    const Visibility* vis;           // Embree's BVHs; null before the scene is built
    const Gathering& gathering;      // the leaf list, the enclosure table and the gather plan
    const DirectLight& direct_light;
    const FinalGather& output;       // the trace, once made
    const Pockets& pockets;          // their escape rays
    const std::vector<std::vector<int>>& tri_prim;  // per object: Embree triangle -> primitive
};

class MemoryBudget {
public:
    // The limit in bytes: max_memory_mb, or when that is 0 half the physical memory (4 GiB when
    // the system does not say).
    explicit MemoryBudget(double max_memory_mb);
    double limit() const { return limit_; }

    // Estimated bytes the solve holds with `more` links and nodes: nodes and links in their
    // chunks, Embree's BVHs, the gathering's leaf list, enclosure table and plan, the direct
    // light, the tables (measure_tables), and the final gather's trace (the one made, or the
    // forecast of the next).
    double estimate(const MemoryView& v, size_t more_links = 0, size_t more_nodes = 0) const;
    // Whether that estimate passes the limit (refinement asks before it links or splits).
    bool over(const MemoryView& v, size_t more_links, size_t more_nodes) const {
        return estimate(v, more_links, more_nodes) > limit_;
    }

    // The scene's arrays, the hierarchy's tables but its nodes, pockets' rays and the Embree
    // triangle map, measured after a build or an update (they change only then), since
    // estimate runs at every split.
    void measure_tables(const MemoryView& v);
    // The final gather's trace for the links as they stand, forecast from the output points'
    // leaves and the links that reach them (0 without a final gather).
    void forecast_output(const MemoryView& v);
    // Before each wave of links: forecast_output again when the links have doubled since, or
    // near the limit; once the output is traced, never.
    void follow_forecast(const MemoryView& v);
    // Bytes of the last forecast (Stats::gather_forecast_bytes).
    double output_forecast() const { return output_forecast_; }

private:
    double limit_ = 0;
    double tables_bytes_ = 0;
    double output_forecast_ = 0;
    int64_t output_forecast_links_ = 0;  // live links when the forecast was made
};

}  // namespace radiosity
