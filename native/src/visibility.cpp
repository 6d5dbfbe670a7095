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
}

Visibility::~Visibility() {
    for (RTCScene s : object_scenes_)
        if (s) rtcReleaseScene(s);
    if (top_) rtcReleaseScene(top_);
    if (device_) rtcReleaseDevice(device_);
}

void Visibility::add_object(int object, const std::vector<Vec3>& tv) {
    if (object >= int(object_scenes_.size())) {
        object_scenes_.resize(object + 1, nullptr);
        instance_geom_.resize(object + 1, -1);
    }
    if (tv.empty()) return;
    RTCScene s = rtcNewScene(device_);
    rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    const size_t nt = tv.size() / 3;
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), tv.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), nt));
    for (size_t i = 0; i < tv.size(); ++i) {
        vb[3 * i] = float(tv[i].x);
        vb[3 * i + 1] = float(tv[i].y);
        vb[3 * i + 2] = float(tv[i].z);
        ib[i] = unsigned(i);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(s);
    check_device(device_, "object build");
    object_scenes_[object] = s;

    RTCGeometry inst = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(inst, s);
    const float id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, id);
    rtcCommitGeometry(inst);
    instance_geom_[object] = int(rtcAttachGeometry(top_, inst));
    if (int(geom_object_.size()) <= instance_geom_[object]) geom_object_.resize(instance_geom_[object] + 1, -1);
    geom_object_[instance_geom_[object]] = object;
    rtcReleaseGeometry(inst);
}

void Visibility::remove_object(int object) {
    if (object < 0 || object >= int(instance_geom_.size())) return;
    if (instance_geom_[object] >= 0) {
        rtcDetachGeometry(top_, unsigned(instance_geom_[object]));
        geom_object_[instance_geom_[object]] = -1;  // Embree may hand the id to a later object
        instance_geom_[object] = -1;
    }
    if (object_scenes_[object]) {
        rtcReleaseScene(object_scenes_[object]);
        object_scenes_[object] = nullptr;
    }
    check_device(device_, "object removal");
}

void Visibility::set_object_transform(int object, const Rigid& placement) {
    if (object < 0 || object >= int(instance_geom_.size()) || instance_geom_[object] < 0) return;
    RTCGeometry inst = rtcGetGeometry(top_, unsigned(instance_geom_[object]));
    const std::array<double, 12> m = placement.rows();
    float f[12];
    for (int i = 0; i < 12; ++i) f[i] = float(m[i]);
    rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, f);
    rtcCommitGeometry(inst);
}

void Visibility::commit() {
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
    unsigned g = rh.hit.instID[0];
    return g < geom_object_.size() ? geom_object_[g] : -1;
}

}  // namespace radiosity
