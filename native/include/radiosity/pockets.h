// Pockets: finds which surfaces see only each other (closed pockets, Node::pocket) with escape
// rays, and keeps each surface's rays so that an update casts again only those a change may alter.
#pragma once
#include <cstdint>
#include <vector>

#include "radiosity/hierarchy.h"
#include "radiosity/settings.h"
#include "radiosity/visibility.h"

namespace radiosity {

class Pockets {
public:
    // What one escape ray of a surface hit: the side of the surface (-1: none, the back of a
    // one-sided polygon, or a removed one) and how far along the ray (the ray's length when
    // it hit nothing).
    struct Ray {
        int side;
        double reach;
    };
    // What escape rays are cast into: Embree's scene, per object the primitive each of its
    // Embree triangles belongs to, and the settings (seed, threads). Held for one call only.
    struct Sight {
        const Visibility& vis;
        const std::vector<std::vector<int>>& tri_prim;
        const Settings& settings;
    };

    // Every surface's closed pocket, written into Node::pocket down its element tree, and the
    // clusters' pocket sets. With `changed` (after moves only: the moved objects' old and new
    // boxes) and `moved` (per object), a surface that did not move keeps the recorded outcome
    // of each ray that meets none of the boxes before its hit (records()).
    void compute(Hierarchy& h, const Sight& sight, const std::vector<Aabb>* changed = nullptr,
                 const std::vector<char>* moved = nullptr);
    // Pockets again after placements or topology changed; false when one of the first
    // `known_surfaces` surfaces that survives changed pocket, or a new one landed in a closed
    // pocket of old ones (which links may exist changed: the caller solves in full).
    bool reseal(Hierarchy& h, const Sight& sight, size_t known_surfaces, const std::vector<Aabb>* changed = nullptr,
                const std::vector<char>* moved = nullptr);
    // Appends what each of `count` escape rays of surface s hits. With `old` (that surface's
    // rays as recorded, same stream) a ray that meets none of `changed` before its hit keeps
    // its record instead of being cast.
    void rays(const Hierarchy& h, const Sight& sight, int s, int count, uint64_t stream, std::vector<Ray>& hits,
              const std::vector<Aabb>* changed = nullptr, const std::vector<Ray>* old = nullptr) const;

    // Per surface: its escape rays at the last compute (kept for the next update).
    const std::vector<std::vector<Ray>>& records() const { return records_; }
    // Closed pockets besides the main space, and the surfaces in them (Stats).
    int64_t closed_pockets() const { return closed_pockets_; }
    int64_t pocket_surfaces() const { return pocket_surfaces_; }

private:
    // compute's last step: every live surface's element tree gets its component's pocket
    // (`component`: per surface its representative; `open`, `area`: per representative), and
    // main_pocket_ and the counts follow.
    void label(Hierarchy& h, const std::vector<size_t>& live, const std::vector<int>& component,
               const std::vector<char>& open, const std::vector<double>& area);

    // compute's confirmation after a move: per component representative, whether its
    // confirmation of the last compute still holds (see pockets.cpp).
    std::vector<char> kept_confirmed(const Hierarchy& h, const std::vector<size_t>& live, const std::vector<int>& rep,
                                     const std::vector<char>& open, int largest, const std::vector<int>& was,
                                     const std::vector<Aabb>& changed, const std::vector<char>& moved) const;
    std::vector<std::vector<Ray>> records_;
    int unconfirmed_ = -1;  // the largest closed pocket's label at the last compute: not confirmed
    int main_pocket_ = 0;  // the pocket of the largest space (open space, or a closed room)
    int64_t closed_pockets_ = 0, pocket_surfaces_ = 0;
};

}  // namespace radiosity
