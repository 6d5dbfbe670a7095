// PendingEdits: what the solver's setters record between updates (moves, material changes)
// until an update or a full solve takes it, and each object's placement, kept from one update
// to the next. Objects added and removed are recorded by Topology (topology.h).
#pragma once
#include <map>
#include <utility>
#include <vector>

#include "radiosity/rigid.h"

namespace radiosity {

class PendingEdits {
public:
    // --- Recorded by the setters.
    // `object` is to be placed at `pose` (internal frame), in place of a move recorded before.
    void record_move(int object, const Rigid& pose) { moves_[object] = pose; }
    // A removed object's pending move, forgotten.
    void drop_move(int object) { moves_.erase(object); }
    // Emission, reflectance, a texture or a light changed.
    void record_materials() { materials_ = true; }

    // --- What is pending.
    bool any() const { return !moves_.empty() || materials_; }
    bool materials() const { return materials_; }
    const std::map<int, Rigid>& moves() const { return moves_; }

    // --- Taken by the update or full solve that applies them; they are no longer pending.
    std::map<int, Rigid> take_moves() { return std::exchange(moves_, {}); }
    bool take_materials() { return std::exchange(materials_, false); }

    // --- Kept per object from one update to the next.
    // Each object's placement (internal frame), for as many objects as fit_poses last said:
    // an object added since has none until an update or a full solve builds it.
    const std::vector<Rigid>& poses() const { return poses_; }
    void fit_poses(size_t objects) { poses_.resize(objects); }
    void place(int object, const Rigid& pose) { poses_[size_t(object)] = pose; }
    // A removed object's slot: back at its geometry as given.
    void unplace(int object) {
        if (size_t(object) < poses_.size()) poses_[size_t(object)] = Rigid{};
    }

private:
    std::map<int, Rigid> moves_;
    bool materials_ = false;
    std::vector<Rigid> poses_;
};

}  // namespace radiosity
