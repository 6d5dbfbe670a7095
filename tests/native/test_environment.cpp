// The world as an equirectangular map (environment.h, lights.cpp): its convention and sampling,
// a constant map against the uniform sky, and maps bright in one part of the sphere against
// closed forms on an open plane.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "radiosity/random.h"
#include "test_util.h"

using namespace radiosity;
using namespace radiosity::testing;

namespace {

SceneDesc floor_scene(int n) {
    SceneDesc s;
    scenes::add_grid(s, "floor", -1, {Vec3{-2, -2, 0}, Vec3{2, -2, 0}, Vec3{2, 2, 0}, Vec3{-2, 2, 0}}, n, n,
                     Rgb::all(0.5), Rgb{});
    return s;
}

// A map whose texel holds f(direction of its centre).
template <class F>
std::shared_ptr<const EnvMap> make_map(int w, int h, const F& f) {
    std::vector<Rgb> t(size_t(w) * h);
    for (int i = 0; i < h; ++i)
        for (int j = 0; j < w; ++j) t[size_t(i) * w + j] = f(EnvMap::direction((j + 0.5) / w, 1 - (i + 0.5) / h));
    return std::make_shared<const EnvMap>(w, h, std::move(t));
}

LightDesc world(std::shared_ptr<const EnvMap> env, Rgb intensity = Rgb::all(1)) {
    LightDesc l;
    l.name = "world";
    l.type = LightDesc::Type::Sky;
    l.intensity = intensity;
    l.env = std::move(env);
    return l;
}

std::vector<Rgb> rgb(const std::vector<float>& v) {
    std::vector<Rgb> out(v.size() / 3);
    for (size_t i = 0; i < out.size(); ++i) out[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    return out;
}

}  // namespace

TEST(Environment, DirectionsMatchTheConventionAndTheTexels) {
    // The centre of the image looks along +X, a quarter to the right along -Y, the top row up.
    const Vec3 c = EnvMap::direction(0.5, 0.5), q = EnvMap::direction(0.75, 0.5), up = EnvMap::direction(0.3, 1.0);
    EXPECT_NEAR(c.x, 1, 1e-12);
    EXPECT_NEAR(q.y, -1, 1e-12);
    EXPECT_NEAR(up.z, 1, 1e-12);
    const int w = 16, h = 8;
    std::vector<Rgb> t(w * h);
    for (int i = 0; i < w * h; ++i) t[size_t(i)] = Rgb::all(i);
    EnvMap m(w, h, t);
    for (int i = 0; i < h; ++i)
        for (int j = 0; j < w; ++j)
            EXPECT_EQ(m.radiance(EnvMap::direction((j + 0.5) / w, 1 - (i + 0.5) / h)).r, double(i * w + j));
}

TEST(Environment, SamplingFollowsItsDensity) {
    // Texels drawn in proportion to mean radiance x solid angle: radiance / pdf is the map's
    // integral for every sample, and the density returned is the one pdf() gives.
    auto m = make_map(32, 16, [](const Vec3& d) { return Rgb{1 + d.x, 2 + d.z * d.z, 0.1}; });
    Rng rng(7);
    const double total = 4 * kPi * m->mean().mean();
    for (int k = 0; k < 2000; ++k) {
        double pdf = 0;
        const Vec3 d = m->sample(rng.next(), rng.next(), pdf);
        ASSERT_NEAR(length(d), 1.0, 1e-9);
        ASSERT_GT(pdf, 0);
        EXPECT_NEAR(pdf, m->pdf(d), 1e-9 * pdf);
        EXPECT_NEAR(m->radiance(d).mean() / pdf, total, 1e-9 * total);
    }
    // The integral against the closed form of the smooth function (texels at their centres).
    EXPECT_NEAR(m->mean().r, 1.0, 2e-3);
    EXPECT_NEAR(m->mean().g, 2 + 1.0 / 3, 2e-2);
    EXPECT_THROW(EnvMap(2, 2, std::vector<Rgb>(3)), std::invalid_argument);
    EXPECT_THROW(EnvMap(1, 1, {Rgb{-1, 0, 0}}), std::invalid_argument);
}

TEST(Environment, AConstantMapEqualsTheUniformSky) {
    // A floor with a box on it: occlusion, interreflection, the final gather's sky included.
    auto build = [](LightDesc l) {
        SceneDesc s = floor_scene(6);
        scenes::add_box(s, "box", -1, Vec3{-0.5, -0.5, 0.0}, Vec3{0.5, 0.5, 1.0}, 3, Rgb{0.7, 0.35, 0.2}, Rgb{});
        s.add_light(l);
        return s;
    };
    const Rgb L{0.4, 0.6, 0.8};
    LightDesc uniform;
    uniform.name = "world";
    uniform.type = LightDesc::Type::Sky;
    uniform.intensity = L;
    Solver a(build(uniform), Settings::preset("HIGH"));
    a.solve();
    Solver b(build(world(make_map(64, 32, [&](const Vec3&) { return L; }))), Settings::preset("HIGH"));
    b.solve();
    for (int o = 0; o < 2; ++o) {
        const auto ra = rgb(a.corner_radiance(o)), rb = rgb(b.corner_radiance(o));
        ASSERT_EQ(ra.size(), rb.size());
        double num = 0, den = 0;
        for (size_t c = 0; c < ra.size(); ++c)
            for (int k = 0; k < 3; ++k) {
                num += (ra[c][k] - rb[c][k]) * (ra[c][k] - rb[c][k]);
                den += ra[c][k] * ra[c][k];
            }
        double sa = 0, sb = 0;
        for (size_t c = 0; c < ra.size(); ++c) sa += ra[c].b, sb += rb[c].b;
        // Both are Monte Carlo: per corner they differ by the noise of two estimators
        // (measured 2.1 % and 2.6 % at HIGH), on average by far less (0.2 %, 0.4 %).
        EXPECT_LT(std::sqrt(num / den), 0.04) << "object " << o;
        EXPECT_NEAR(sb / sa, 1.0, 0.01) << "object " << o;
    }
}

TEST(Environment, HalfASkyAndASunPatchOnAnOpenPlane) {
    // Only the half of the sky toward +X shines (radiance 2): a plane facing up receives
    // E = 2 * pi / 2, radiance rho E / pi = 0.5.
    {
        SceneDesc s = floor_scene(2);
        s.add_light(world(make_map(64, 32, [](const Vec3& d) { return d.x > 0 ? Rgb::all(2) : Rgb{}; })));
        Solver solver(s, Settings::preset("MEDIUM"));
        solver.solve();
        for (const Rgb& v : rgb(solver.corner_radiance(0))) EXPECT_NEAR(v.r, 0.5, 0.01);
    }
    // One texel at about 30 degrees elevation, the rest black: E = L x (integral of cos over the
    // texel), its solid angle x the sine of its centre's elevation to first order.
    {
        const int w = 64, h = 32, i = 10, j = 40;
        std::vector<Rgb> t(size_t(w) * h);
        t[size_t(i) * w + j] = Rgb{1000, 500, 250};
        auto m = std::make_shared<const EnvMap>(w, h, t);
        const double lat_hi = kPi * (0.5 - double(i) / h), lat_lo = kPi * (0.5 - double(i + 1) / h);
        // Integral of sin(lat) over the texel: (2 pi / w) * int sin cos dlat.
        const double E = 1000 * (2 * kPi / w) * 0.5 * (std::sin(lat_hi) * std::sin(lat_hi) - std::sin(lat_lo) * std::sin(lat_lo));
        SceneDesc s = floor_scene(2);
        s.add_light(world(m));
        Solver solver(s, Settings::preset("MEDIUM"));
        solver.solve();
        for (const Rgb& v : rgb(solver.corner_radiance(0))) {
            EXPECT_NEAR(v.r, 0.5 * E / kPi, 0.01 * 0.5 * E / kPi);
            EXPECT_NEAR(v.g, 0.5 * v.r, 1e-6 * v.r);
        }
    }
}

TEST(Environment, OnlyTheWorldTakesAMapAndChangingItUpdates) {
    LightDesc sun;
    sun.name = "sun";
    sun.type = LightDesc::Type::Sun;
    sun.intensity = Rgb::all(1);
    sun.env = make_map(4, 2, [](const Vec3&) { return Rgb::all(1); });
    EXPECT_THROW(sun.validate(), InputError);
    SceneDesc s = floor_scene(2);
    s.add_light(world(make_map(16, 8, [](const Vec3&) { return Rgb::all(1); })));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    solver.set_light(0, world(make_map(16, 8, [](const Vec3&) { return Rgb::all(3); })));
    solver.update();
    for (const Rgb& v : rgb(solver.corner_radiance(0))) EXPECT_NEAR(v.r, 1.5, 0.03);
}

TEST(Environment, CornerMaterialsShadeEachCorner) {
    // A per-corner reflectance and emission change the output only: radiance = e + rho x the
    // irradiance there (here the uniform sky: E / pi = L everywhere on an open plane).
    SceneDesc s = floor_scene(2);
    LightDesc sky;
    sky.name = "world";
    sky.type = LightDesc::Type::Sky;
    sky.intensity = Rgb::all(2);
    s.add_light(sky);
    ObjectDesc& o = s.objects_mut()[0];
    for (size_t c = 0; c < o.corner_count(); ++c) o.corner_reflectance.push_back(Rgb::all(c % 2 ? 0.25 : 0.75));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    auto v = rgb(solver.corner_radiance(0));
    for (size_t c = 0; c < v.size(); ++c) EXPECT_NEAR(v[c].r, 2 * (c % 2 ? 0.25 : 0.75), 1e-3);
    const size_t nc = v.size();
    solver.set_corner_materials(0, {}, std::vector<Rgb>(nc, Rgb{1, 0, 0}));
    v = rgb(solver.corner_radiance(0));
    for (size_t c = 0; c < nc; ++c) EXPECT_NEAR(v[c].r, 1 + 2 * 0.5, 1e-3);  // the polygons' rho again
    EXPECT_THROW(solver.set_corner_materials(0, std::vector<Rgb>(nc + 1), {}), InputError);
    EXPECT_THROW(solver.set_corner_materials(0, std::vector<Rgb>(nc, Rgb::all(1.0)), {}), InputError);
    ObjectDesc bad = s.objects()[0];
    bad.corner_reflectance.assign(3, Rgb{});
    SceneDesc s2;
    EXPECT_THROW(s2.add_object(bad), InputError);
}

TEST(Environment, TexturePiecesGiveElementsAndPointsTheirOwnValue) {
    // One 4 x 4 m quad whose texture is dark on its left half and bright on its right, given as
    // 2 x 2 pieces (textures.py's cut copy): the quad's elements take the mean of the pieces
    // inside them, a point the nearest piece's value; the polygon's own value is their mean.
    SceneDesc s = floor_scene(1);
    ObjectDesc& o = s.objects_mut()[0];
    const Rgb dark = Rgb::all(0.2), bright = Rgb::all(0.8);
    for (double y : {-1.0, 1.0})
        for (double x : {-1.0, 1.0}) o.pieces.push_back({0, Vec3{x, y, 0}, 4.0, x < 0 ? dark : bright});
    SceneDesc bad = s;
    bad.objects_mut()[0].pieces[1].face = 1;  // the floor has one polygon
    EXPECT_THROW(SceneDesc().add_object(bad.objects()[0]), InputError);
    bad.objects_mut()[0].pieces[1] = {0, Vec3{0, 0, 0}, 1.0, Rgb::all(1.0)};
    EXPECT_THROW(SceneDesc().add_object(bad.objects()[0]), InputError);
    SceneDesc ok;
    ok.add_object(s.objects()[0]);
    Hierarchy h;
    h.build(ok, true);
    ASSERT_EQ(h.surfaces.size(), 2u);  // front and back of the two-sided quad
    for (const Surface& sf : h.surfaces) {
        const int root = sf.root;
        EXPECT_NEAR(h.nodes[size_t(root)].rho.r, 0.5, 1e-12);  // all four pieces' mean
        h.subdivide(root);
        const std::vector<int> children = h.nodes[size_t(root)].children;  // (a copy: nodes move)
        for (int c : children) {
            const Node& e = h.nodes[size_t(c)];
            const double rho = e.rho.r;  // (subdivide below may move the nodes)
            EXPECT_NEAR(rho, e.center.x < h.to_internal(Vec3{0, 0, 0}).x ? 0.2 : 0.8, 1e-12);
            // A grandchild holds no piece's centre: it takes the nearest piece's value.
            h.subdivide(c);
            for (int g : h.nodes[size_t(c)].children) EXPECT_NEAR(h.nodes[size_t(g)].rho.r, rho, 1e-12);
        }
        EXPECT_NEAR(h.rho_at(root, h.to_internal(Vec3{-1.9, 1.5, 0})).r, 0.2, 1e-12);
        EXPECT_NEAR(h.rho_at(root, h.to_internal(Vec3{0.1, -1.5, 0})).r, 0.8, 1e-12);
    }
    // Through the solver, lit by a point lamp 1 m over the middle (the floor is refined under
    // it, so the corners' leaves lie in one half each): a left corner reflects a quarter of
    // what the mirror-image right corner does (the output reads its leaf's rho); new pieces
    // (set_texture_pieces) swap that at the next update.
    s.add_light(point_light({0, 0, 1}, 100));
    Solver solver(s, Settings::preset("MEDIUM"));
    solver.solve();
    const ObjectDesc& f = solver.scene().objects()[0];
    auto halves = [&]() {
        const std::vector<Rgb> v = rgb(solver.corner_radiance(0));
        double left = 0, right = 0;
        for (size_t c = 0; c < v.size(); ++c) (f.vertices[size_t(f.corner_verts[c])].x < 0 ? left : right) += v[c].r;
        return std::make_pair(left, right);
    };
    const auto [left, right] = halves();
    EXPECT_NEAR(left / right, 0.25, 1e-3) << left << " " << right;
    std::vector<TexturePiece> swapped = s.objects()[0].pieces;
    for (TexturePiece& q : swapped) q.rho = q.position.x < 0 ? bright : dark;
    solver.set_texture_pieces(0, swapped);
    solver.update();
    const auto [left2, right2] = halves();
    EXPECT_NEAR(left2 / right2, 4.0, 4e-3) << left2 << " " << right2;
    EXPECT_THROW(solver.set_texture_pieces(0, {{3, Vec3{}, 1.0, dark}}), InputError);
}

TEST(Environment, TexturePiecesGiveElementsTheirOwnEmission) {
    // A quad emitting on its right half only (a textured emission's pieces): the polygon emits
    // their mean, each child its half's, and its radiance swaps the emission with it.
    SceneDesc s = floor_scene(1);
    ObjectDesc& o = s.objects_mut()[0];
    o.emission[0] = Rgb::all(2.5);
    for (double y : {-1.0, 1.0})
        for (double x : {-1.0, 1.0}) o.pieces.push_back({0, Vec3{x, y, 0}, 4.0, Rgb::all(0.5), Rgb::all(x < 0 ? 0.0 : 5.0)});
    o.pieces_emit = true;
    SceneDesc ok;
    ok.add_object(s.objects()[0]);
    Hierarchy h;
    h.build(ok, true);
    const int root = h.surfaces[0].root;
    EXPECT_NEAR(h.nodes[size_t(root)].emission.r, 2.5, 1e-12);
    h.subdivide(root);
    for (int c : std::vector<int>(h.nodes[size_t(root)].children)) {
        const Node& e = h.nodes[size_t(c)];
        const double want = e.center.x < h.to_internal(Vec3{0, 0, 0}).x ? 0.0 : 5.0;
        EXPECT_NEAR(e.emission.r, want, 1e-12);
        EXPECT_NEAR(e.L.r, want, 1e-12);
    }
    // Without the flag the pieces' emission is not read.
    ok.objects_mut()[0].pieces_emit = false;
    Hierarchy h2;
    h2.build(ok, true);
    h2.subdivide(h2.surfaces[0].root);
    for (int c : std::vector<int>(h2.nodes[size_t(h2.surfaces[0].root)].children))
        EXPECT_NEAR(h2.nodes[size_t(c)].emission.r, 2.5, 1e-12);
    o.pieces[2].emission = Rgb{-1, 0, 0};
    EXPECT_THROW(SceneDesc().add_object(o), InputError);
}
