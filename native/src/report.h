// What a finished run reports that is read off the solution's parts (Stats, stats.h): the links
// by kind, the elements light reaches, and the warnings its result deserves. Free functions
// over the parts, const: the solver calls them at the end of a solve or an update.
#pragma once
#include <cstdint>

#include "radiosity/direct_light.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link_store.h"
#include "radiosity/settings.h"
#include "radiosity/stats.h"

namespace radiosity {

// Sets the link counts of `s`: active links by kind (cluster or surface; between the
// environment and objects), history and occluded links.
void count_links(const Hierarchy& h, const LinkStore& links, Stats& s);
// The leaves of surfaces that light reaches: an emitter, a surface with links or a lamp's
// light, or one facing a sender of a cluster link above it (a back face nothing lights
// costs none).
int64_t lit_elements(const Hierarchy& h, const LinkStore& links, const DirectLight& direct);
// Appends to s.warnings what the result that stands after a solve or an update deserves
// (an update starts from none: an earlier solve's warning, such as a full-solve fallback, no
// longer applies): polygons that could not be triangulated, memory over `limit` (the bake
// holds `held` bytes), a cap that stopped refinement.
void add_result_warnings(const Hierarchy& h, const Settings& settings, double held, double limit, Stats& s);

}  // namespace radiosity
