#include "radiosity/visibility.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace radiosity {

namespace {
// Embree takes a ray only with float coordinates within 1.8e18 (its ray.valid() check, an
// assertion in Debian's build that ends the process); such segments are not traced.
bool traceable(const Vec3& a, const Vec3& b) {
    constexpr double kMax = 1e18;
    for (int k = 0; k < 3; ++k)
        if (!(std::fabs(a[k]) <= kMax && std::fabs(b[k]) <= kMax)) return false;
    return true;
}

// Embree's memory monitor: allocations arrive as positive byte counts, releases as negative.
bool monitor(void* user, ssize_t bytes, bool /*post*/) {
    static_cast<std::atomic<int64_t>*>(user)->fetch_add(int64_t(bytes), std::memory_order_relaxed);
    return true;
}

// This thread's slot of a ray count: threads take slots in turn, the first time they count.
unsigned ray_slot(unsigned slots) {
    static std::atomic<unsigned> next{0};
    thread_local const unsigned slot = next.fetch_add(1, std::memory_order_relaxed);
    return slot % slots;
}

void check_device(RTCDevice d, const char* what) {
    RTCError e = rtcGetDeviceError(d);
    if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("Embree error in ") + what + ": " + std::to_string(int(e)));
}
}  // namespace

Visibility::Visibility() {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree device could not be created");
    rtcSetDeviceMemoryMonitorFunction(device_, monitor, &bytes_);
    top_ = rtcNewScene(device_);
    rtcSetSceneFlags(top_, RTC_SCENE_FLAG_ROBUST);
    shared_ = rtcNewScene(device_);
    rtcSetSceneFlags(shared_, RTC_SCENE_FLAG_ROBUST);
}

Visibility::~Visibility() {
    for (RTCScene s : object_scenes_)
        if (s) rtcReleaseScene(s);
    if (top_) rtcReleaseScene(top_);
    if (shared_) rtcReleaseScene(shared_);
    if (device_) rtcReleaseDevice(device_);
}

namespace {
// A triangle geometry of `count` vertices (three a triangle) written by `put` (float x, y, z
// per vertex), committed; the caller attaches and releases it.
template <class Put>
RTCGeometry triangles(RTCDevice device, size_t count, Put put) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), count));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), count / 3));
    for (size_t i = 0; i < count; ++i) {
        put(i, vb + 3 * i);
        ib[i] = unsigned(i);
    }
    rtcCommitGeometry(g);
    return g;
}

// Attaches g to scene s and records which object it holds in `object_of` (by geometry id:
// Embree may hand a detached geometry's id to a later one).
unsigned attach(RTCScene s, RTCGeometry g, int object, std::vector<int>& object_of) {
    const unsigned id = rtcAttachGeometry(s, g);
    if (object_of.size() <= id) object_of.resize(id + 1, -1);
    object_of[id] = object;
    rtcReleaseGeometry(g);
    return id;
}

RTCGeometry instance_of(RTCDevice device, RTCScene s) {
    RTCGeometry inst = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, s);
    const float id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, id);
    rtcCommitGeometry(inst);
    return inst;
}
}  // namespace

void Visibility::fit(int object) {
    if (object < int(object_scenes_.size())) return;
    object_scenes_.resize(object + 1, nullptr);
    instance_geom_.resize(object + 1, -1);
    shared_geom_.resize(object + 1, -1);
    vertex_count_.resize(object + 1, 0);
}

void Visibility::add_object(int object, const std::vector<Vec3>& tv) {
    fit(object);
    if (tv.empty()) return;
    RTCGeometry g = triangles(device_, tv.size(), [&tv](size_t i, float* v) {
        v[0] = float(tv[i].x), v[1] = float(tv[i].y), v[2] = float(tv[i].z);
    });
    shared_geom_[object] = int(attach(shared_, g, object, shared_object_));
    vertex_count_[size_t(object)] = tv.size();
    shared_changed_ = true;
    check_device(device_, "object build");
}

void Visibility::own_scene(int object) {
    const unsigned gid = unsigned(shared_geom_[object]);
    RTCGeometry old = rtcGetGeometry(shared_, gid);
    const auto* ov = static_cast<const float*>(rtcGetGeometryBufferData(old, RTC_BUFFER_TYPE_VERTEX, 0));
    RTCScene s = rtcNewScene(device_);
    rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = triangles(device_, vertex_count_[size_t(object)], [ov](size_t i, float* v) {
        v[0] = ov[3 * i], v[1] = ov[3 * i + 1], v[2] = ov[3 * i + 2];
    });
    rtcAttachGeometry(s, g);  // its scene's only geometry: hits name the object by instance
    rtcReleaseGeometry(g);
    rtcCommitScene(s);
    rtcDetachGeometry(shared_, gid);
    shared_object_[gid] = -1;
    shared_geom_[object] = -1;
    shared_changed_ = true;
    object_scenes_[object] = s;
    instance_geom_[object] = int(attach(top_, instance_of(device_, s), object, geom_object_));
    check_device(device_, "object build");
}

void Visibility::remove_object(int object) {
    if (object < 0 || object >= int(instance_geom_.size())) return;
    if (shared_geom_[object] >= 0) {
        rtcDetachGeometry(shared_, unsigned(shared_geom_[object]));
        shared_object_[size_t(shared_geom_[object])] = -1;
        shared_geom_[object] = -1;
        shared_changed_ = true;
    }
    if (instance_geom_[object] >= 0) {
        rtcDetachGeometry(top_, unsigned(instance_geom_[object]));
        geom_object_[instance_geom_[object]] = -1;
        instance_geom_[object] = -1;
    }
    if (object_scenes_[object]) {
        rtcReleaseScene(object_scenes_[object]);
        object_scenes_[object] = nullptr;
    }
    check_device(device_, "object removal");
}

void Visibility::set_object_transform(int object, const Rigid& placement) {
    if (object < 0 || object >= int(instance_geom_.size())) return;
    if (shared_geom_[object] >= 0) {
        if (placement.identity()) return;  // where it was given: stays shared
        own_scene(object);
    }
    if (instance_geom_[object] < 0) return;
    RTCGeometry inst = rtcGetGeometry(top_, unsigned(instance_geom_[object]));
    const std::array<double, 12> m = placement.rows();
    float f[12];
    for (int i = 0; i < 12; ++i) f[i] = float(m[i]);
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, f);
    rtcCommitGeometry(inst);
}

void Visibility::commit() {
    if (shared_changed_ || shared_instance_ < 0) {
        rtcCommitScene(shared_);
        if (shared_instance_ < 0) {
            shared_instance_ = int(attach(top_, instance_of(device_, shared_), -1, geom_object_));
        } else {
            rtcCommitGeometry(rtcGetGeometry(top_, unsigned(shared_instance_)));  // its bounds changed
        }
        shared_changed_ = false;
    }
    rtcCommitScene(top_);
    check_device(device_, "scene commit");
}

void Visibility::count_ray() const {
    rays_[ray_slot(kRaySlots)].n.fetch_add(1, std::memory_order_relaxed);
}

uint64_t Visibility::rays() const {
    uint64_t total = 0;
    for (const RayCount& c : rays_) total += c.n.load(std::memory_order_relaxed);
    return total;
}

bool Visibility::occluded(const Vec3& a, const Vec3& b, double near) const {
    count_ray();
    if (!traceable(a, b)) return false;
    Vec3 d = b - a;
    double len = length(d);
    if (len <= near + eps_) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray{};
    ray.org_x = float(a.x);
    ray.org_y = float(a.y);
    ray.org_z = float(a.z);
    ray.dir_x = float(d.x / len);
    ray.dir_y = float(d.y / len);
    ray.dir_z = float(d.z / len);
    ray.tnear = float(near);
    ray.tfar = float(len - eps_);
    ray.mask = 0xFFFFFFFFu;
    ray.time = 0.f;
    rtcOccluded1(top_, &ctx, &ray);
    return ray.tfar < 0;  // Embree sets tfar = -inf on a hit
}

int Visibility::hit_object(const Vec3& a, const Vec3& b, double near, Vec3* hit, int* triangle) const {
    count_ray();
    if (!traceable(a, b)) return -1;
    Vec3 d = b - a;
    double len = length(d);
    if (len <= near) return -1;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh{};
    rh.ray.org_x = float(a.x);
    rh.ray.org_y = float(a.y);
    rh.ray.org_z = float(a.z);
    rh.ray.dir_x = float(d.x / len);
    rh.ray.dir_y = float(d.y / len);
    rh.ray.dir_z = float(d.z / len);
    rh.ray.tnear = float(near);
    rh.ray.tfar = float(len);
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(top_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return -1;
    if (hit) *hit = a + d * (double(rh.ray.tfar) / len);
    if (triangle) *triangle = int(rh.hit.primID);
    const unsigned g = rh.hit.instID[0];
    if (int(g) == shared_instance_) return rh.hit.geomID < shared_object_.size() ? shared_object_[rh.hit.geomID] : -1;
    return g < geom_object_.size() ? geom_object_[g] : -1;
}

}  // namespace radiosity
