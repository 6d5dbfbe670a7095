// Ray-cast visibility between points, on Embree 3. Objects that never moved share one Embree
// scene (one BVH over all their triangles, an object a geometry), instanced once into the
// top-level scene: a ray descends one tree, not one per object whose box it meets (in a
// furnished room the walls' box holds every other). An object's first placement other than
// where it was given moves it into a scene of its own, instanced, so a rigid move after that
// only re-transforms its instance (the shared scene is rebuilt once, without it).
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "radiosity/rigid.h"
#include "radiosity/vec.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace radiosity {

class Visibility {
public:
    Visibility();
    ~Visibility();
    Visibility(const Visibility&) = delete;
    Visibility& operator=(const Visibility&) = delete;

    // Triangles in world space (into the shared scene); an object with none is left out.
    void add_object(int object, const std::vector<Vec3>& tri_vertices);
    // Takes an object's triangles out (rays pass where it was); its id is not reused. Takes
    // effect at the next commit().
    void remove_object(int object);
    // Placement of an object relative to where its triangles were given. Takes effect at the
    // next commit().
    void set_object_transform(int object, const Rigid& placement);
    void commit();
    // Offset (scene units) kept from both segment ends, so a ray never hits the surfaces it
    // joins; relative to scene size so results do not change when the scene is scaled.
    void set_epsilon(double eps) { eps_ = eps; }

    // True when something blocks the open segment a-b (the first and last `epsilon` of it
    // excluded). Thread-safe.
    bool occluded(const Vec3& a, const Vec3& b) const { return occluded(a, b, eps_); }
    // Same with an explicit near offset: for rays whose origin is already lifted off its
    // surface and that must see geometry right next to it (escape rays).
    bool occluded(const Vec3& a, const Vec3& b, double near) const;
    // The object first hit along a -> b (beyond `near`), -1 if nothing; writes the hit point
    // and the index of the hit triangle within its object (in add_object's order).
    int hit_object(const Vec3& a, const Vec3& b, double near, Vec3* hit, int* triangle = nullptr) const;
    uint64_t rays() const;
    // Bytes Embree holds for this device now (its BVHs, geometry buffers and instances), as
    // its memory monitor reports them.
    int64_t bytes() const { return bytes_.load(std::memory_order_relaxed); }

private:
    RTCDeviceTy* device_ = nullptr;
    RTCSceneTy* top_ = nullptr;
    RTCSceneTy* shared_ = nullptr;       // the objects never moved
    int shared_instance_ = -1;           // its instance's geometry id in top_
    bool shared_changed_ = false;        // ... to rebuild at the next commit()
    std::vector<int> shared_geom_;       // per object: its geometry id in shared_, -1 if not there
    std::vector<int> shared_object_;     // per geometry id in shared_: its object
    std::vector<size_t> vertex_count_;   // per object: its triangles' vertices
    std::vector<RTCSceneTy*> object_scenes_;
    std::vector<int> instance_geom_;  // per object: geometry id in top_, -1 if none
    std::vector<int> geom_object_;    // per geometry id in top_: its object
    void fit(int object);
    // An object's triangles moved out of shared_ into a scene of its own, instanced in top_.
    void own_scene(int object);
    double eps_ = 1e-6;
    // Rays cast, counted in one slot per thread (a slot to a cache line): threads that shared
    // one counter would pass its line between cores on every ray.
    struct alignas(64) RayCount { std::atomic<uint64_t> n{0}; };
    static constexpr unsigned kRaySlots = 16;
    void count_ray() const;
    mutable std::array<RayCount, kRaySlots> rays_;
    std::atomic<int64_t> bytes_{0};
};

}  // namespace radiosity
