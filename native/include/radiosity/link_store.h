// LinkStore: every link made, gathering, history (3.4) or dead, under ids that never change,
// and the bookkeeping that ties them to the hierarchy, which only its own calls change: an
// active link is in its ends' in_links and out_links, a refined link heads the list of the
// links it was refined into, and the live count is what the max_links cap reads.
#pragma once
#include <cstdint>
#include <vector>

#include "radiosity/chunked.h"
#include "radiosity/hierarchy.h"
#include "radiosity/link.h"

namespace radiosity {

class LinkStore {
    // In chunks that never move (chunked.h): growing copies no link.
    using Links = Chunked<Link, 14>;

public:
    // Stores `l` and returns its id: in its ends' link lists when active, among its parent's
    // children when it has one.
    int add(Hierarchy& h, Link l);
    // Gathering again (a history link taken back, an opened view); no longer occluded.
    void activate(Hierarchy& h, int id);
    // Out of its ends' link lists (refined into others, or fully occluded): kept as history.
    void deactivate(Hierarchy& h, int id);
    // A link and the links it was refined into, for good (the slot stays, dead).
    void kill(Hierarchy& h, int id);
    // The links `id` was refined into, for good (un-refinement takes `id` back instead).
    void kill_refined(Hierarchy& h, int id);
    void clear();

    size_t size() const { return links_.size(); }
    int64_t live() const { return live_; }  // links not dead
    // A link's values (its evaluation, the oracle's flags). Its `active`, `dead`, `parent`
    // and history list are changed by the calls above only.
    Link& operator[](size_t id) { return links_[id]; }
    const Link& operator[](size_t id) const { return links_[id]; }
    using iterator = Links::iterator;
    using const_iterator = Links::const_iterator;
    iterator begin() { return links_.begin(); }
    iterator end() { return links_.end(); }
    const_iterator begin() const { return links_.begin(); }
    const_iterator end() const { return links_.end(); }
    // Bytes the store holds once `more` links are added (for the memory estimate).
    double bytes(size_t more = 0) const { return links_.bytes(more); }

private:
    Links links_;
    int64_t live_ = 0;
};

}  // namespace radiosity
