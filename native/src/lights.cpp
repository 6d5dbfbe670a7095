// Direct light of Blender point, spot and sun lights and of a uniform world at the leaf
// elements (see lights.h), which DirectLight (direct_light.h) keeps per node. Each leaf keeps the area mean of its four children's estimates as
// its direct term and their spread as the refinement criterion, so a leaf split for its direct
// light already knows what its children will see.
#include "radiosity/lights.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "radiosity/direct_light.h"
#include "radiosity/parallel.h"
#include "radiosity/random.h"
#include "radiosity/replay.h"

namespace radiosity {

void LightDesc::validate() const {
    auto bad = [this](const std::string& what) { throw InputError("light '" + name + "': " + what); };
    if (int(type) < 0 || int(type) > 3) bad("unknown type");
    if (!finite(position) || !finite(direction)) bad("position or direction is not finite");
    if (!finite(intensity)) bad("intensity is not finite");
    for (int k = 0; k < 3; ++k)
        if (intensity[k] < 0) bad("negative intensity");
    if ((type == Type::Spot || type == Type::Sun) && !(length(direction) > 0)) bad("zero direction");
    if (!(std::isfinite(radius) && radius >= 0)) bad("radius must be >= 0");
    if (!(std::isfinite(angle) && angle >= 0 && angle <= kPi)) bad("sun angle must be in [0, pi]");
    if (!(std::isfinite(spot_size) && spot_size > 0 && spot_size <= kPi)) bad("spot size must be in (0, pi]");
    if (!(std::isfinite(spot_blend) && spot_blend >= 0 && spot_blend <= 1)) bad("spot blend must be in [0, 1]");
    if (env && type != Type::Sky) bad("only the world (sky) takes an environment map");
}

int SceneDesc::add_light(LightDesc l) {
    l.validate();
    l.direction = normalize(l.direction);
    lights_.push_back(std::move(l));
    return int(lights_.size()) - 1;
}

namespace {

// A light in the solver's internal frame (geometry divided by `unit`): intensities of point
// and spot lights are scaled by 1/unit^2 so that I / d_internal^2 is the world irradiance.
struct ILight {
    LightDesc::Type type;
    Vec3 pos, dir;
    double radius = 0, cos_half = -1, smooth = 0, sun_cos = 1;
    bool cos_falloff = false;
    Rgb I;
    const EnvMap* env = nullptr;  // Sky: radiance I x env(d), owned by the scene's LightDesc
    uint64_t salt = 0;
};

std::vector<ILight> internal_lights(const SceneDesc& scene, const Hierarchy& h) {
    std::vector<ILight> out;
    uint64_t k = 0;
    for (const LightDesc& d : scene.lights()) {
        ++k;
        if (d.intensity.max() <= 0 || (d.env && d.env->empty_of_light())) continue;
        ILight l;
        l.env = d.env.get();
        l.type = d.type;
        l.pos = (d.position - h.origin) / h.unit;
        l.dir = normalize(d.direction);
        l.radius = d.radius / h.unit;
        l.I = d.type == LightDesc::Type::Point || d.type == LightDesc::Type::Spot ? d.intensity / (h.unit * h.unit)
                                                                                   : d.intensity;
        l.cos_half = d.type == LightDesc::Type::Spot ? std::cos(0.5 * d.spot_size) : -1.0;
        // Cycles' spot edge: smoothstep over the outer `blend` part of (1 - cos_half).
        l.smooth = (1.0 - l.cos_half) * d.spot_blend;
        l.cos_falloff = d.spot_cos_falloff;
        l.sun_cos = std::cos(0.5 * d.angle);
        l.salt = Hierarchy::mix(0x11947u, k);
        out.push_back(l);
    }
    return out;
}

double spot_mask(const ILight& l, const Vec3& from_light) {
    if (l.type != LightDesc::Type::Spot) return 1.0;
    double z = dot(from_light, l.dir);
    if (z <= l.cos_half) return 0.0;
    double m = 1.0;
    double t = z - l.cos_half;
    if (l.smooth > 0 && t < l.smooth) {
        double x = t / l.smooth;
        m = x * x * (3 - 2 * x);
    }
    return l.cos_falloff ? m * z : m;
}

// What one child's samples say about a light.
struct Sampled {
    Rgb mean;           // irradiance / pi, visibility included
    double var = 0;     // variance of the mean (max channel)
    double unocc = 0;   // mean without visibility (max channel)
    bool partial = false;  // some samples that could see the light did, some did not
};

// The two numbers that pick sample i of m on a light (a direction or a point on it): with
// `strata`, the first k x k samples (k = floor(sqrt(m))) fill a jittered k x k grid of the
// unit square, the rest are uniform. Each sample is still uniform on its own, so the mean
// stays unbiased, and a smooth integrand (the sky seen past a chair, a sun's soft shadow)
// comes out with far less noise than from independent samples.
std::pair<double, double> light_sample_uv(int i, int m, bool strata, Rng& rng) {
    const double a = rng.next(), b = rng.next();
    if (!strata) return {a, b};
    const int k = int(std::sqrt(double(m)));
    if (i >= k * k) return {a, b};
    return {(i % k + a) / k, (i / k + b) / k};
}

// The frames a light's samples are drawn in: the sun's cap of directions about the
// direction toward it, the sky's hemisphere about the receiving plane's normal n.
struct SampleFrames {
    Vec3 su, sv;  // sun cap frame
    Vec3 nu, nv;  // hemisphere frame
    SampleFrames(const ILight& l, const Vec3& n) {
        if (l.type == LightDesc::Type::Sun) frame(-l.dir, su, sv);
        if (l.type == LightDesc::Type::Sky) frame(n, nu, nv);
    }
};

// One light sample from o (the point p lifted off its plane of normal n), drawn by the
// numbers (a, b): the scalar factor of its colour col (the light's I, a map's times its
// radiance there) with visibility (f) and without (u). `touching`: the point lies on a
// contact, and sees nothing; `far`: the length of a ray toward the sun or the sky.
struct LightSample {
    const Vec3& p;
    const Vec3& o;
    const Vec3& n;
    double a, b;
    bool touching;
    double far;
    double f = 0, u = 0;
    Rgb col;
};

// A sample of a world with a map: half the samples (i even) cosine-weighted, half by the
// map's luminance x solid angle (a sun in the map), each weighted by the mixture of both
// densities (the balance heuristic): neither a bright spot nor a uniform map is missed.
// False when the sample sees nothing of the world (below the plane).
template <class Rays>
bool sky_map_sample(const ILight& l, const SampleFrames& fr, int i, Rays& vis, LightSample& s) {
    double pm = 0;
    Vec3 d;
    if (i % 2) {
        d = l.env->sample(s.a, s.b, pm);
    } else {
        d = cosine_direction(fr.nu, fr.nv, s.n, s.a, s.b);
        pm = l.env->pdf(d);
    }
    const double c = dot(s.n, d);
    if (c <= 0) return false;
    const double mix = 0.5 * (c / kPi + pm);
    if (!(mix > 0)) return false;
    s.col = l.I * l.env->radiance(d);
    s.u = c / kPi / mix;
    if (!s.touching && !vis.occluded(s.o, s.o + d * s.far, 0.0)) s.f = s.u;
    return true;
}

// A point's or an element's shadow rays, replayed (ReplayedRays) from the same record (same
// seed and lights) where they meet no moved box. With the ball its rays start from, the
// uniform sky's samples outside the boxes' window keep their outcome unmade (sky_kept).
struct LampRayStream : ReplayedRays<LampRays> {
    using ReplayedRays::ReplayedRays;
    bool occluded(const Vec3& a, const Vec3& b) { return take(a, b, -1); }
    bool occluded(const Vec3& a, const Vec3& b, double near) { return take(a, b, near); }
    bool take(const Vec3& a, const Vec3& b, double near) {
        const int k = out.count;
        if (old && k < old->count && !changed.meets(a, b)) return keep();
        ++out.count;
        const bool blocked = near < 0 ? vis.occluded(a, b) : vis.occluded(a, b, near);
        ++cast;
        record(k, blocked);
        return blocked;
    }
    // The next ray's recorded outcome, kept.
    bool keep() {
        const int k = out.count++;
        const bool blocked = (old->blocked[size_t(k) >> 6] >> (k & 63)) & 1;
        record(k, blocked);
        return blocked;
    }
    void record(int k, bool blocked) {
        if ((size_t(k) >> 6) >= out.blocked.size()) out.blocked.push_back(0);
        if (blocked) out.blocked[size_t(k) >> 6] |= uint64_t(1) << (k & 63);
    }
    void set_origins(const Vec3& c, double r) { origin = c, origin_r = r; }
    Vec3 origin;
    double origin_r = -1;  // < 0: the origins unknown, every sample made
    CosineWindow sky;
};

// For the uniform sky's samples of one light from a plane (frame nu, nv, n): the window of
// those a replay must make (a fresh trace makes them all).
template <class Rays>
void aim_sky(Rays&, const Vec3&, const Vec3&, const Vec3&) {}
void aim_sky(LampRayStream& rs, const Vec3& nu, const Vec3& nv, const Vec3& n) {
    rs.sky = rs.old && rs.origin_r >= 0 ? CosineWindow(rs.changed.all, rs.origin, rs.origin_r, nu, nv, n) : CosineWindow();
}
// Whether the sample (a, b) keeps its recorded outcome (`blocked`) without its ray.
template <class Rays>
bool sky_kept(Rays&, double, double, bool&) { return false; }
bool sky_kept(LampRayStream& rs, double a, double b, bool& blocked) {
    if (!rs.old || rs.out.count >= rs.old->count || rs.sky.may_meet(a, b)) return false;
    blocked = rs.keep();
    return true;
}

// A uniform world: a cosine-weighted direction, so the estimator of E/pi is L_sky x visibility.
template <class Rays>
void sky_sample(const SampleFrames& fr, Rays& vis, LightSample& s) {
    s.u = 1.0;
    if (s.touching) return;
    bool blocked = false;
    if (sky_kept(vis, s.a, s.b, blocked)) {
        if (!blocked) s.f = 1.0;
        return;
    }
    const Vec3 d = cosine_direction(fr.nu, fr.nv, s.n, s.a, s.b);
    if (!vis.occluded(s.o, s.o + d * s.far, 0.0)) s.f = 1.0;
}

// A sun: a direction uniform on its cap of directions (toward the sun).
template <class Rays>
void sun_sample(const ILight& l, const SampleFrames& fr, Rays& vis, LightSample& s) {
    double ct = 1 - s.a * (1 - l.sun_cos), st = std::sqrt(std::max(0.0, 1 - ct * ct)), phi = 2 * kPi * s.b;
    Vec3 d = fr.su * (std::cos(phi) * st) + fr.sv * (std::sin(phi) * st) + (-l.dir) * ct;
    double c = dot(s.n, d);
    if (c <= 0) return;
    s.u = c / kPi;
    if (!s.touching && !vis.occluded(s.o, s.o + d * s.far, 0.0)) s.f = s.u;
}

// A point or spot light: a disk of the light's radius facing the receiving point (Cycles'
// model of a point light with a radius), radiance I / (pi r^2): uniform samples on it.
template <class Rays>
void lamp_sample(const ILight& l, Rays& vis, LightSample& s) {
    Vec3 q = l.pos;
    Vec3 w = normalize(s.p - l.pos);
    if (l.radius > 0) {
        Vec3 u, v;
        frame(w, u, v);
        double r = l.radius * std::sqrt(s.a), phi = 2 * kPi * s.b;
        q = l.pos + u * (r * std::cos(phi)) + v * (r * std::sin(phi));
    }
    Vec3 d = q - s.p;
    double d2 = length2(d);
    if (d2 <= 0) return;
    Vec3 dn = d / std::sqrt(d2);
    double cp = dot(s.n, dn), cq = l.radius > 0 ? -dot(w, dn) : 1.0;
    if (cp <= 0 || cq <= 0) return;
    double mask = spot_mask(l, w);
    if (mask <= 0) return;
    s.u = cp * cq * mask / (d2 * kPi);
    if (!s.touching && !vis.occluded(s.o, q)) s.f = s.u;
}

// Monte Carlo estimate of irradiance / pi over the points `where(i, rng)` gives (on a plane
// of normal n) from one light, with visibility; m samples. With `strata` (a single point:
// `where` constant) the light's samples are stratified (light_sample_uv); over an element
// the points are stratified instead, and the two must not be paired by index.
// Shadow rays through `vis`: a Visibility, or a LampRayStream (a point's recorded rays).
template <class Where, class Contact, class Rays>
Sampled estimate(const ILight& l, const Where& where, const Vec3& n, int m, Rng& rng, Rays& vis, double lift,
                 double far, const Contact& contact, bool strata = false) {
    Rgb s1;  // sum of the samples' irradiance / pi, visibility included
    double s2 = 0, s_unocc = 0;
    int seen = 0, hidden = 0;
    const SampleFrames fr(l, n);
    if (l.type == LightDesc::Type::Sky && !l.env) aim_sky(vis, fr.nu, fr.nv, n);
    // A map: the samples estimate only what occluders take away from the unoccluded
    // irradiance, known in closed form (a control variate: an open floor under a sun gets its
    // exact light, not the noise of a few samples of a bright spot).
    const Rgb open = l.env ? l.I * l.env->irradiance(n) / kPi : Rgb{};
    for (int i = 0; i < m; ++i) {
        const Vec3 p = where(i, rng);
        const Vec3 o = p + n * lift;
        // (A map's two halves, cosine-weighted and by the map, are stratified apart.)
        const bool halves = l.type == LightDesc::Type::Sky && l.env;
        const auto [a, b] = halves ? light_sample_uv(i / 2, i % 2 ? m / 2 : (m + 1) / 2, strata, rng)
                                   : light_sample_uv(i, m, strata, rng);
        LightSample s{p, o, n, a, b, contact(p), far, 0.0, 0.0, l.I};
        if (halves && sky_map_sample(l, fr, i, vis, s)) {
            if (s.u > 0) (s.f > 0 ? seen : hidden)++;
            // What this sample says is missing from `open` (col x (f - u) <= 0).
            const double g = (s.u - s.f) * s.col.max();
            s1 += s.col * (s.f - s.u);
            s2 += g * g;
            continue;
        }
        switch (l.type) {
            case LightDesc::Type::Sky:  // (a map's sample below the plane: f = u = 0)
                if (!l.env) sky_sample(fr, vis, s);
                break;
            case LightDesc::Type::Sun: sun_sample(l, fr, vis, s); break;
            default: lamp_sample(l, vis, s);
        }
        const double g = s.f * s.col.max();
        s1 += s.col * s.f;
        s2 += g * g;
        s_unocc += s.u * s.col.max();
        if (s.u > 0) (s.f > 0 ? seen : hidden)++;
    }
    Sampled r;
    r.mean = s1 / m;
    const double mean = l.env ? -r.mean.max() : r.mean.max();
    r.var = m > 1 ? std::max(0.0, s2 / m - mean * mean) / (m - 1) : mean * mean;
    r.unocc = s_unocc / m;
    if (l.env) {
        r.mean = cmax(open + r.mean, Rgb{});
        r.unocc = open.max();
        if (hidden > 0 && seen == 0) r.mean = Rgb{};  // a point in contact, or wholly covered
    }
    r.partial = seen > 0 && hidden > 0;
    return r;
}

template <class Rays>
PointLight direct_light_with(const SceneDesc& scene, const Hierarchy& h, Rays& vis, const Vec3& x, const Vec3& n,
                             bool covered, int m, uint64_t seed) {
    PointLight out;
    const double far = 4.0 * h.scene_diag, lift = 1e-5 * h.scene_diag;
    for (const ILight& l : internal_lights(scene, h)) {
        Rng rng(Hierarchy::mix(seed ^ l.salt, 0x70u));
        const bool sky = l.type == LightDesc::Type::Sky;
        // A point light without a radius casts a hard shadow: one ray says all there is.
        const bool hard = (l.type == LightDesc::Type::Point || l.type == LightDesc::Type::Spot) && l.radius <= 0;
        const int mm = sky ? 4 * m : hard ? 1 : m;
        const Sampled r = estimate(l, [&x](int, Rng&) { return x; }, n, mm, rng, vis, lift, far,
                                   [covered](const Vec3&) { return covered; }, true);
        out.E += r.mean;
        out.partial |= r.partial;
        out.rays += mm;
    }
    return out;
}

}  // namespace

PointLight direct_light_at(const SceneDesc& scene, const Hierarchy& h, const Visibility& vis, const Vec3& x,
                           const Vec3& n, bool covered, int m, uint64_t seed) {
    return direct_light_with(scene, h, vis, x, n, covered, m, seed);
}

PointLight direct_light_replay(const SceneDesc& scene, const Hierarchy& h, const Visibility& vis, const Vec3& x,
                               const Vec3& n, int m, uint64_t seed, const LampRays* old,
                               const std::vector<Aabb>* changed, LampRays& out) {
    LampRayStream rs(vis, old, changed);
    rs.set_origins(x, 2e-5 * h.scene_diag);  // (direct_light_with lifts them 1e-5 of it off the plane)
    PointLight r = direct_light_with(scene, h, rs, x, n, false, m, seed);
    r.rays = int(rs.cast);
    out = std::move(rs.out);
    return r;
}

int element_shadow_rays(int rays_per_link, LightDesc::Type type) {
    // Half the link rays (an element costs two links), four times that for the sky, whose
    // hemisphere integral is noisier than a small light's. Fewer would hide real shadow edges
    // behind the noise allowance of DirectLight::compute.
    const int m = std::max(4, rays_per_link / 2);
    return type == LightDesc::Type::Sky ? 4 * m : m;
}

namespace {

// Per element: a node strictly below it is referenced. Children have larger ids than their
// parents (subdivide appends), so one pass from the back sees every child first.
std::vector<char> link_below(const Hierarchy& h, const std::vector<char>& referenced) {
    std::vector<char> below(h.nodes.size(), 0);
    for (size_t i = h.nodes.size(); i-- > 0;) {
        const Node& n = h.nodes[i];
        if (n.dead || n.is_cluster() || n.parent < 0) continue;
        if (referenced[i] || below[i]) below[n.parent] = 1;
    }
    return below;
}

}  // namespace

Rgb DirectLight::direct(int id) const {
    return size_t(id) < have_.size() && have_[id] == kLit ? direct_[id] : Rgb{};
}

double DirectLight::spread(int id) const {
    return size_t(id) < have_.size() && have_[id] == kLit ? double(spread_[id]) : 0.0;
}

std::vector<float> DirectLight::first_bounce(const Hierarchy& h) const {
    // light_initial's sweep (solver_lights.cpp) leaves this radiance, before any link exists,
    // so the settlements (3.5) a full solve's first linking makes hold for it.
    const size_t nn = h.nodes.size();
    std::vector<Rgb> sum(nn);
    std::vector<double> area(nn, 0.0);
    std::vector<float> out(nn, 0.f);
    for (size_t i = nn; i-- > 0;) {  // children (larger ids) before their parents
        const Node& n = h.nodes[i];
        if (n.dead || n.is_cluster()) continue;
        if (n.children.empty()) {
            const Rgb d = i < direct_.size() ? direct_[i] : Rgb{};
            sum[i] = (n.emission + n.rho * d) * n.area;
            area[i] = n.area;
        }
        if (area[i] > 0) out[i] = float((sum[i] / area[i]).max());
        if (n.parent >= 0 && !h.nodes[n.parent].is_cluster()) {
            sum[n.parent] += sum[i];
            area[n.parent] += area[i];
        }
    }
    return out;
}

double DirectLight::power(const SceneDesc& scene, const Hierarchy& h, double total_area) {
    // In the units of the emitters' sum (Hierarchy::surface_totals): a Lambertian emitter of
    // radiance L and area A radiates pi L A, so each light counts as power / pi.
    double p = 0;
    for (const ILight& l : internal_lights(scene, h)) {
        switch (l.type) {
            case LightDesc::Type::Point: p += 4 * l.I.max(); break;
            case LightDesc::Type::Spot: p += 2 * (1 - l.cos_half) * l.I.max(); break;
            case LightDesc::Type::Sun: p += 0.25 * total_area * l.I.max() / kPi; break;  // a convex scene's mean projection
            case LightDesc::Type::Sky:  // half the sky, unoccluded
                p += 0.5 * total_area * (l.env ? (l.I * l.env->mean()).max() : l.I.max());
                break;
        }
    }
    return p;
}

double DirectLight::bytes(const SceneDesc& scene, int rays_per_link) const {
    // Per lit node, its recorded shadow rays (compute: four children, 4x for the sky).
    if (rays_.empty()) return 0.0;
    int per_node = 0;
    for (const LightDesc& d : scene.lights()) per_node += 4 * element_shadow_rays(rays_per_link, d.type);
    return double(rays_.capacity()) * (sizeof(LampRays) + 8.0 * std::ceil(per_node / 64.0));
}

void DirectLight::clear() { *this = DirectLight{}; }

void DirectLight::relight() {
    std::fill(have_.begin(), have_.end(), 0);
    recheck_ = true;
}

void DirectLight::forget_contacts() {
    contacts_.clear();
    kept_contacts_.clear();
    contact_boxes_.clear();
}

void DirectLight::moved_contacts(const std::vector<Aabb>& boxes) {
    stash_contacts();
    contact_boxes_.insert(contact_boxes_.end(), boxes.begin(), boxes.end());
}

void DirectLight::stash_contacts() {
    if (!contacts_.empty()) kept_contacts_ = std::move(contacts_);
    contacts_.clear();
}

bool DirectLight::take_recheck() { return std::exchange(recheck_, false); }

void DirectLight::resize(size_t nn) {
    direct_.resize(nn);
    spread_.resize(nn, 0.f);
    have_.resize(nn, kNone);
    split_.resize(nn, 0);
}

void DirectLight::invalidate(const Hierarchy& h, const std::vector<Rigid>& poses, const std::vector<Aabb>* replay) {
    // Every shadow may have changed. A node whose box meets a moved one is lit afresh (what
    // touches it, and so which of its rays are cast, may differ).
    if (poses != poses_) {
        const bool replaying = replay && !poses_.empty();
        bool stale_left = false;
        for (uint8_t v : have_) stale_left |= v == kStale;
        if (!stale_left) clips_.clear();
        if (replaying) {
            clips_.insert(clips_.end(), replay->begin(), replay->end());
            for (size_t id = 0; id < have_.size(); ++id) {
                if (have_[id] == kNone) continue;
                const Node& n = h.nodes[id];
                bool near = n.dead;
                for (const Aabb& c : *replay) near = near || c.overlaps(n.box);
                have_[id] = near || id >= rays_.size() ? kNone : kStale;
            }
        } else {
            std::fill(have_.begin(), have_.end(), kNone);
        }
        recheck_ = !poses_.empty();
        // (Placements change where an update moves objects, and moved_contacts says where, or
        // in a full solve, which clears everything: the contacts are only set aside here.)
        stash_contacts();
        poses_ = poses;
    }
    resize(h.nodes.size());
}

void DirectLight::prepare(const Hierarchy& h, const Sight& sight, const std::vector<int>& leaves,
                          const std::vector<Rigid>& poses, const std::vector<Aabb>* replay) {
    if (sight.scene.lights().empty()) return;
    invalidate(h, poses, replay);
    std::vector<int> todo;
    for (int id : leaves)
        if (have_[id] != kLit) todo.push_back(id);
    compute(h, sight, todo);
}

namespace {

// The surfaces of other objects (and front sides of other polygons of its own) lying on
// surface si within `tol` of its plane and facing it, in the order a walk of the cluster tree
// by boxes meets them.
std::vector<int> surface_contacts(const Hierarchy& h, const SceneDesc& scene, size_t si, double tol) {
    std::vector<int> out;
    const Node& n = h.nodes[h.surfaces[si].root];
    if (n.dead) return out;  // of a removed object
    const Aabb b = n.box.grown(tol);
    const bool own_back = h.surfaces[si].back;
    // Polygons of its own object looked at, at most: the pieces of a fanned n-gon all share
    // its apex, so every piece's box meets every other's (100k pieces: 10^10 tests). Real
    // meshes meet a few neighbours.
    int same_left = 4096;
    std::vector<int> stack{h.root};
    while (!stack.empty()) {
        const int id = stack.back();
        stack.pop_back();
        const Node& m = h.nodes[id];
        if (!b.overlaps(m.box)) continue;
        // Within one object only front sides touch (below): a back surface skips its own
        // object's clusters (a 100k-piece fanned disc: every piece's box meets every other's).
        if (m.is_cluster()) {
            if (m.object == n.object && (own_back || same_left <= 0)) continue;
            for (int c : m.children) stack.push_back(c);
            continue;
        }
        // Another object's polygon, or a front side of another polygon of the same object (a
        // chair's back resting on its seat: Cycles finds that contact unlit too). Not the
        // back of a neighbouring piece of the same plane (a two-sided fanned n-gon).
        if (m.object == n.object && (own_back || --same_left < 0 || h.surfaces[size_t(m.surface)].back)) continue;
        if (h.surfaces[size_t(m.surface)].prim == h.surfaces[si].prim || dot(m.normal, n.normal) > -1 + 1e-9) continue;
        if (std::fabs(dot(m.poly.v[0] - n.poly.v[0], n.normal)) > tol) continue;
        if (!scene.objects()[m.object].occluder) continue;
        out.push_back(m.surface);
    }
    return out;
}

}  // namespace

void DirectLight::find_contacts(const Hierarchy& h, const SceneDesc& scene, int threads) {
    // Surfaces of other objects lying in the same plane and facing the other way: where they
    // overlap, the two touch (a box standing on a floor). Rays from there start between the
    // two and would escape through the other one; Cycles finds such points unlit, and so
    // does a real contact. Found by walking the cluster tree by boxes.
    if (contacts_.size() == h.surfaces.size()) return;
    const auto t0 = std::chrono::steady_clock::now();
    const double tol = 1e-7 * h.scene_diag;
    // After moves, a surface whose box grown by tol meets no moved object's old or new box
    // (contact_boxes_) keeps its contacts: a moved surface lay within its old box and lies
    // within its new one, so it was not and is not among them, and the others, and the order
    // the walk meets them in, are as they were. The rest are found again.
    std::vector<int> todo;
    if (kept_contacts_.size() == h.surfaces.size()) {
        contacts_ = std::move(kept_contacts_);
        for (size_t si = 0; si < h.surfaces.size(); ++si) {
            const Aabb b = h.nodes[h.surfaces[si].root].box.grown(tol);
            if (std::any_of(contact_boxes_.begin(), contact_boxes_.end(), [&](const Aabb& c) { return c.overlaps(b); }))
                todo.push_back(int(si));
        }
    } else {
        contacts_.assign(h.surfaces.size(), {});
        for (size_t si = 0; si < h.surfaces.size(); ++si) todo.push_back(int(si));
    }
    kept_contacts_.clear();
    contact_boxes_.clear();
    parallel_for(todo.size(), threads, [&](size_t k) {
        contacts_[size_t(todo[k])] = surface_contacts(h, scene, size_t(todo[k]), tol);
    }, 32);
    contact_work_.surfaces += int64_t(todo.size());
    contact_work_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int DirectLight::contact(const Hierarchy& h, int surface, const Vec3& p) const {
    if (size_t(surface) >= contacts_.size()) return -1;
    const double tol = 1e-9 * h.scene_diag;
    for (int t : contacts_[surface]) {
        const Node& m = h.nodes[h.surfaces[t].root];
        if (within_edges(m.poly, m.normal, p, tol)) return t;
    }
    return -1;
}

bool DirectLight::corner_in_contact(const Hierarchy& h, const Primitive& p, int k) const {
    // Cycles shades each corner inside its own face: at the foot of a box standing on the
    // floor, the floor corners under the box are unlit and those beside it lit. Corners in
    // contact are therefore not averaged with the others (output.cpp).
    if (contacts_.empty() || p.front < 0) return false;
    const Vec3 inside = p.poly.v[k] + (p.poly.centroid() - p.poly.v[k]) * 1e-4;
    return contact(h, p.front, inside) >= 0;
}

void DirectLight::compute(const Hierarchy& h, const Sight& sight, const std::vector<int>& ids) {
    if (ids.empty()) return;
    find_contacts(h, sight.scene, sight.settings.threads);
    const std::vector<ILight> ls = internal_lights(sight.scene, h);
    const double far = 4.0 * h.scene_diag, lift = 1e-5 * h.scene_diag;
    if (rays_.size() < h.nodes.size()) rays_.resize(h.nodes.size());
    parallel_for(ids.size(), sight.settings.threads, [&](size_t i) {
        const int id = ids[i];
        const Node& n = h.nodes[id];
        // Its shadow rays, replayed where a move left the node stale (invalidate).
        const bool stale = have_[id] == kStale;
        LampRayStream rs(sight.vis, stale ? &rays_[id] : nullptr, stale ? &clips_ : nullptr);
        if (stale) {
            // Every ray leaves the element's plane upward: with all that moved below its
            // lowest corner, the node is lit as it was. Else the ball its rays start from.
            double lowest = 1e300, reach = 0;
            const Vec3 centre = n.poly.centroid();
            for (int v = 0; v < n.poly.n; ++v) {
                lowest = std::min(lowest, dot(n.normal, n.poly.v[size_t(v)]));
                reach = std::max(reach, length(n.poly.v[size_t(v)] - centre));
            }
            if (std::all_of(clips_.begin(), clips_.end(), [&](const Aabb& b) { return b.max_along(n.normal) < lowest; })) {
                have_[id] = kLit;
                return;
            }
            rs.set_origins(centre, reach + 2 * lift);
        }
        Rgb sum, lo = Rgb::all(1e300), hi = Rgb::all(-1e300);
        double area = 0, var_max = 0, edge = 0;
        for (int k = 0; k < 4; ++k) {
            const Poly c = n.poly.child(k);
            const double a = c.area(), share = c.first_share();
            Rgb e;
            double var = 0;
            for (const ILight& l : ls) {
                Rng rng(Hierarchy::mix(Hierarchy::mix(sight.settings.seed ^ l.salt, n.key), uint64_t(k)));
                const bool sky = l.type == LightDesc::Type::Sky;
                const int mm = element_shadow_rays(sight.settings.rays_per_link, l.type);
                // Stratified over the child along its first coordinate.
                auto where = [&c, share, mm](int s, Rng& g) {
                    const double v = g.next(), u = (s + g.next()) / mm;  // named: the order is every compiler's
                    return c.sample(share, u, v);
                };
                const Sampled r = estimate(l, where, n.normal, mm, rng, rs, lift, far,
                                           [&](const Vec3& p) { return contact(h, n.surface, p) >= 0; });
                e += r.mean;
                if (sky) var += r.var;
                // A shadow edge of a small light crosses this child (the HR visibility error):
                // its light may be anywhere between none and all of the unoccluded value.
                else if (r.partial) edge = std::max(edge, r.unocc);
            }
            sum += e * a;
            area += a;
            lo = cmin(lo, e);
            hi = cmax(hi, e);
            var_max = std::max(var_max, var);
        }
        direct_[id] = area > 0 ? sum / area : Rgb{};
        // Spread of the children beyond what the sky's noise explains (one sigma of a
        // difference: the sky's occlusion is smooth, noise alone must not refine it to the
        // resolution limit), or a small light's shadow edge inside a child.
        spread_[id] = float(std::max({0.0, (hi - lo).max() - std::sqrt(2.0 * var_max), edge}));
        have_[id] = kLit;
        rays_[id] = std::move(rs.out);
    }, 8);
}

void DirectLight::walk(const Hierarchy& h, const Sight& sight, double threshold, const std::vector<char>& link_below,
                       std::vector<int>& lit, std::vector<int>& drop) {
    // Top-down, level by level, as a full solve splits for the light: a node's children are
    // there for the light only if it was split for it and its direct light still varies by
    // more than the threshold. Below a node whose children neither the light nor a link
    // needs nothing is visited, so the splits down there are never evaluated. (Judged
    // bottom-up, a light right above a node's centre would keep its children: they agree with
    // each other by symmetry, so a full solve never splits it, but their own children differ.)
    resize(h.nodes.size());
    std::vector<int> level;
    for (const Surface& s : h.surfaces)
        if (!h.nodes[s.root].dead) level.push_back(s.root);
    while (!level.empty()) {
        std::vector<int> todo, next;
        for (int id : level)
            if (split_[id] && !h.nodes[id].children.empty() && have_[id] != kLit) todo.push_back(id);
        compute(h, sight, todo);
        for (int id : level) {
            const Node& n = h.nodes[id];
            if (n.children.empty()) continue;
            if (split_[id] && n.rho.max() * spread_[id] > threshold) {
                lit.push_back(id);
            } else {
                split_[id] = 0;
                if (!link_below[id]) {
                    drop.push_back(id);
                    continue;
                }
            }
            for (int c : n.children) next.push_back(c);
        }
        level.swap(next);
    }
}

std::vector<int> DirectLight::coarsen(const Hierarchy& h, const Sight& sight, double threshold,
                                      const std::vector<char>& referenced) {
    // 3.4's un-refinement, for lights: done before the direct light of the old leaves is
    // computed again, so the children dropped cost no rays.
    std::vector<int> lit, drop;
    walk(h, sight, threshold, link_below(h, referenced), lit, drop);
    for (int id : drop) {  // their subtrees go with them
        std::vector<int> stack(h.nodes[id].children.begin(), h.nodes[id].children.end());
        while (!stack.empty()) {
            const int c = stack.back();
            stack.pop_back();
            split_[c] = 0;
            stack.insert(stack.end(), h.nodes[c].children.begin(), h.nodes[c].children.end());
        }
    }
    return drop;
}

bool DirectLight::refine(const Hierarchy& h, const Sight& sight, double threshold, const std::vector<int>& leaves,
                         const std::function<bool(int)>& split) {
    std::vector<int> wave;
    for (int id : leaves)
        if (size_t(id) < have_.size() && have_[id] == kLit) wave.push_back(id);
    bool changed = false;
    while (!wave.empty()) {
        std::vector<int> kids;
        for (int id : wave) {
            // `split` grows h.nodes: no reference into it is held across the call.
            if (h.nodes[id].dead || !h.nodes[id].children.empty()) continue;
            if (h.nodes[id].rho.max() * spread_[id] <= threshold || !split(id)) continue;
            for (int c : h.nodes[id].children) kids.push_back(c);
            changed = true;
        }
        resize(h.nodes.size());
        for (int c : kids) split_[h.nodes[c].parent] = 1;
        compute(h, sight, kids);
        wave.swap(kids);
    }
    return changed;
}

void DirectLight::keep(const Hierarchy& h, const Sight& sight, double threshold, std::vector<int>& refs) {
    // Children made for the direct light are referenced by it (pruning must keep them) while
    // the light still varies across their parent and the parent itself stays; otherwise the
    // split is forgotten and the children go like any unreferenced element.
    std::vector<char> referenced(h.nodes.size(), 0);
    for (size_t i = 0; i < refs.size() && i < referenced.size(); ++i) referenced[i] = refs[i] > 0;
    std::vector<int> lit, drop;
    walk(h, sight, threshold, link_below(h, referenced), lit, drop);
    for (int id : lit)
        for (int c : h.nodes[id].children) ++refs[c];
}

}  // namespace radiosity
