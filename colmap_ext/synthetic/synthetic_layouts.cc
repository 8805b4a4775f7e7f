#include "colmap_ext/synthetic/synthetic_layouts.h"

#include <cmath>

#include "colmap_ext/synthetic/room_layouts.h"
#include "colmap_ext/synthetic/synthetic_random.h"
#include "colmap_ext/synthetic/world_builder.h"
#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

using Eigen::Vector3d;

struct Opening {
  double u0, v0, u1, v1;  // wall-local rectangle (metres from the wall centre)
  bool window;            // window (glass, mullions, sill) or door
};

struct WallMaterials {
  int wall, reveal, glass, frame, sill, door;
};

// A plain wall quad with rectangular openings. Each opening is recessed `depth` metres
// into the building (along `inward`) with plain reveals, a textured glass pane or door,
// a mullion cross and a protruding sill: depth discontinuities on a plain wall.
void AddWallWithOpenings(WorldBuilder* b, const Vector3d& center, const Vector3d& u,
                         const Vector3d& v, const Vector3d& inward, double half_u,
                         double half_v, const std::vector<Opening>& openings, double depth,
                         const WallMaterials& mat) {
  ScenePrimitive wall = MakeQuad(center, u, v, half_u, half_v, mat.wall);
  for (const Opening& o : openings) wall.holes.push_back({o.u0, o.v0, o.u1, o.v1});
  b->Add(wall);
  Eigen::Matrix3d axes;
  axes.col(0) = u;
  axes.col(1) = v;
  axes.col(2) = inward;
  for (const Opening& o : openings) {
    const double uc = 0.5 * (o.u0 + o.u1), vc = 0.5 * (o.v0 + o.v1);
    const double hu = 0.5 * (o.u1 - o.u0), hv = 0.5 * (o.v1 - o.v0);
    const Vector3d oc = center + uc * u + vc * v;
    const double pane_depth = o.window ? depth : 0.6 * depth;
    b->Add(MakeQuad(oc + pane_depth * inward, u, v, hu, hv, o.window ? mat.glass : mat.door));
    const Vector3d half_in = 0.5 * pane_depth * inward;
    b->Add(MakeQuad(oc - hu * u + half_in, inward, v, 0.5 * pane_depth, hv, mat.reveal));
    b->Add(MakeQuad(oc + hu * u + half_in, inward, v, 0.5 * pane_depth, hv, mat.reveal));
    b->Add(MakeQuad(oc + hv * v + half_in, u, inward, hu, 0.5 * pane_depth, mat.reveal));
    if (o.v0 > -half_v + 1e-6) {
      b->Add(MakeQuad(oc - hv * v + half_in, u, inward, hu, 0.5 * pane_depth, mat.reveal));
    }
    if (!o.window) continue;
    const Vector3d pane = oc + (pane_depth - 0.06) * inward;
    b->Add(OrientedBox(pane, axes, Vector3d(0.035, hv, 0.04), mat.frame));
    b->Add(OrientedBox(pane + 0.15 * hv * v, axes, Vector3d(hu, 0.035, 0.04), mat.frame));
    b->Add(OrientedBox(oc - (hv + 0.04) * v - 0.06 * inward, axes,
                       Vector3d(hu + 0.12, 0.04, 0.12), mat.sill));
  }
}

void Intrinsics(const LayoutParams& p, double* fx, double* fy, double* cx, double* cy) {
  // ~58 degree horizontal field of view; slightly non-square pixels and an off-centre
  // principal point so that code mixing up fx/fy or cx/cy shows up.
  *fx = 0.9 * p.width;
  *fy = 1.003 * *fx;
  *cx = 0.5 * p.width + 0.0125 * p.width;
  *cy = 0.5 * p.height - 0.01 * p.height;
}

SyntheticLayout BuildIndoor(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  // Room shell: plain materials only (untextured), x in [-3,3], y in [-2.5,2.5], z in [0,2.6].
  const int wall_warm = b.Plain({0.80, 0.77, 0.71});
  const int wall_cool = b.Plain({0.70, 0.74, 0.78});
  const int floor = b.Plain({0.52, 0.44, 0.36});
  const int ceiling = b.Plain({0.86, 0.86, 0.85});
  const int door = b.Plain({0.56, 0.47, 0.38});
  const int sofa = b.Plain({0.42, 0.46, 0.55});
  const double X = 3.0, Y = 2.5, H = 2.6;
  const Vector3d ex = Vector3d::UnitX(), ey = Vector3d::UnitY(), ez = Vector3d::UnitZ();
  b.Add(MakeQuad({0, 0, 0}, ex, ey, X, Y, floor), false);
  b.Add(MakeQuad({0, 0, H}, ex, ey, X, Y, ceiling), false);
  b.Add(MakeQuad({0, Y, H / 2}, ex, ez, X, H / 2, wall_warm), false);
  b.Add(MakeQuad({0, -Y, H / 2}, ex, ez, X, H / 2, wall_warm), false);
  b.Add(MakeQuad({-X, 0, H / 2}, ey, ez, Y, H / 2, wall_cool), false);
  b.Add(MakeQuad({X, 0, H / 2}, ey, ez, Y, H / 2, wall_cool), false);

  // Textured things at several scales.
  const int rug = b.Pattern(TexturePattern::kMixed, {0.62, 0.22, 0.16}, {0.92, 0.82, 0.52}, 0.12);
  const int poster_noise =
      b.Pattern(TexturePattern::kNoise, {0.10, 0.28, 0.58}, {0.95, 0.90, 0.72}, 0.09);
  const int poster_checker =
      b.Pattern(TexturePattern::kChecker, {0.14, 0.14, 0.16}, {0.90, 0.90, 0.84}, 0.08);
  const int picture =
      b.Pattern(TexturePattern::kMixed, {0.20, 0.45, 0.25}, {0.90, 0.85, 0.60}, 0.07);
  const int wood = b.Pattern(TexturePattern::kStripes, {0.42, 0.26, 0.14}, {0.72, 0.52, 0.32},
                             0.05, Vector3d(0.2, 0.1, 1.0));
  const int cloth = b.Pattern(TexturePattern::kMixed, {0.15, 0.25, 0.55}, {0.90, 0.90, 0.95}, 0.06);
  const int ball = b.Pattern(TexturePattern::kNoise, {0.75, 0.12, 0.10}, {0.95, 0.85, 0.20}, 0.07);
  const int bin = b.Pattern(TexturePattern::kStripes, {0.15, 0.45, 0.22}, {0.90, 0.92, 0.88},
                            0.06, Vector3d(0, 0, 1));
  const int metal = b.Pattern(TexturePattern::kNoise, {0.20, 0.20, 0.22}, {0.70, 0.70, 0.72}, 0.03);
  const int books = b.Pattern(TexturePattern::kStripes, {0.55, 0.15, 0.12}, {0.20, 0.35, 0.60},
                              0.035, Vector3d(1, 0.3, 0));
  const int cushion =
      b.Pattern(TexturePattern::kChecker, {0.80, 0.55, 0.20}, {0.30, 0.18, 0.10}, 0.06);
  const int shade = b.Pattern(TexturePattern::kNoise, {0.85, 0.80, 0.65}, {0.55, 0.45, 0.30}, 0.04);

  b.Add(MakeQuad({0.6, Y - 0.01, 1.45}, ex, ez, 0.45, 0.6, poster_noise));
  b.Add(MakeQuad({-1.5, Y - 0.01, 1.75}, ex, ez, 0.3, 0.3, poster_checker));
  b.Add(MakeQuad({-X + 0.01, 0.2, 1.5}, ey, ez, 0.5, 0.35, picture));
  b.Add(MakeQuad({X - 0.01, 0.9, 1.4}, ey, ez, 0.4, 0.5, poster_noise));
  b.Add(MakeQuad({-X + 0.01, 1.5, 1.0}, ey, ez, 0.45, 1.0, door));  // plain door
  b.Add(MakeQuad({0.1, -0.3, 0.004}, ex, ey, 1.0, 0.75, rug));
  b.Add(MakeBox({-2.95, 1.6, 0}, {-1.75, 2.45, 1.0}, wood));                 // cabinet
  b.Add(MakeBox({-2.6, 1.8, 1.0}, {-2.0, 2.2, 1.25}, books));                // books on it
  b.Add(MakeBox({0.6, 0.9, 0.72}, {1.8, 1.7, 0.77}, cloth));                 // table top
  for (double lx : {0.66, 1.74}) {
    for (double ly : {0.96, 1.64}) b.Add(MakeCylinder({lx, ly, 0}, ez, 0.03, 0.72, metal));
  }
  b.Add(MakeSphere({-0.9, 0.5, 0.28}, 0.28, ball));
  b.Add(MakeCylinder({2.3, 1.9, 0}, ez, 0.22, 0.6, bin));
  b.Add(MakeCylinder({-1.2, 2.0, 0}, ez, 0.02, 1.6, metal));  // thin lamp pole
  b.Add(MakeCylinder({-1.2, 2.0, 1.6}, ez, 0.18, 0.25, shade));
  b.Add(MakeYawedBox({1.5, -0.4, 0.2}, {0.25, 0.2, 0.2}, 0.5, books));
  b.Add(MakeYawedBox({-2.1, -0.6, 0.3}, {0.45, 0.9, 0.3}, 0.15, sofa));  // plain sofa block
  b.Add(MakeYawedBox({-2.0, -0.9, 0.68}, {0.25, 0.3, 0.08}, 0.4, cushion));

  SyntheticWorld& w = b.world();
  w.lighting.ambient = 0.32;
  w.lighting.sun_direction = Vector3d(0.5, 0.8, -0.6);
  w.lighting.sun_intensity = 0.35;
  w.lighting.has_point_light = true;
  w.lighting.point_position = Vector3d(0.3, 0.3, 2.1);  // a hanging lamp
  w.lighting.point_power = 1.0;
  w.lighting.point_softness = 0.9;
  w.lighting.exposure = 0.8;
  w.background.color = Vector3d(0, 0, 0);  // unreachable: the room is closed
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  double fx, fy, cx, cy;
  Intrinsics(p, &fx, &fy, &cx, &cy);
  SynthRng rng(SynthHash(p.seed, 0xca3e7a5ULL));
  const int n = p.num_views;
  const double span = std::min(3.6, 0.4 * (n - 1));
  for (int i = 0; i < n; ++i) {
    const double a = Spread(i, n);
    const Vector3d center(a * span + rng.Uniform(-0.05, 0.05), -1.9 + 0.25 * (i % 2),
                          1.45 + 0.12 * ((i % 3) - 1) + rng.Uniform(-0.04, 0.04));
    // Look around: yaw across the room, mostly slightly down, one in three a bit up.
    const double yaw = (a * 26.0 + rng.Uniform(-3, 3)) * kDegToRad;
    const double pitch = ((i % 3 == 2 ? 2.0 : -13.0) + rng.Uniform(-3, 3)) * kDegToRad;
    const Vector3d dir(std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch),
                       std::sin(pitch));
    const double roll = rng.Uniform(-6, 6) * kDegToRad;
    layout.cameras.push_back(
        LookAtCamera(center, center + 3.0 * dir, ez, roll, p.width, p.height, fx, fy, cx, cy));
  }
  return layout;
}

SyntheticLayout BuildFacade(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  const Vector3d ex = Vector3d::UnitX(), ey = Vector3d::UnitY(), ez = Vector3d::UnitZ();
  WallMaterials main_mat;
  main_mat.wall = b.Plain({0.86, 0.80, 0.68});
  main_mat.reveal = main_mat.wall;
  main_mat.glass = b.Pattern(TexturePattern::kNoise, {0.10, 0.13, 0.18}, {0.52, 0.62, 0.74}, 0.35);
  main_mat.frame = b.Plain({0.92, 0.92, 0.90});
  main_mat.sill = b.Pattern(TexturePattern::kNoise, {0.55, 0.55, 0.52}, {0.80, 0.78, 0.74}, 0.06);
  main_mat.door = b.Pattern(TexturePattern::kStripes, {0.35, 0.20, 0.10}, {0.60, 0.40, 0.22},
                            0.08, Vector3d(1, 0, 0.15));
  WallMaterials side_mat = main_mat;
  side_mat.wall = b.Plain({0.76, 0.72, 0.66});
  side_mat.reveal = side_mat.wall;
  const int paving = b.Pattern(TexturePattern::kMixed, {0.36, 0.34, 0.32}, {0.62, 0.60, 0.56}, 0.3);
  const int metal = b.Pattern(TexturePattern::kNoise, {0.12, 0.12, 0.14}, {0.45, 0.45, 0.48}, 0.05);
  const int lamp = b.Pattern(TexturePattern::kNoise, {0.90, 0.88, 0.70}, {0.50, 0.48, 0.40}, 0.05);
  const int bark = b.Pattern(TexturePattern::kStripes, {0.25, 0.18, 0.10}, {0.45, 0.34, 0.22},
                             0.06, Vector3d(1, 0.2, 0.1));
  const int leaves = b.Pattern(TexturePattern::kNoise, {0.10, 0.30, 0.08}, {0.45, 0.62, 0.20}, 0.22);
  const int wood = b.Pattern(TexturePattern::kStripes, {0.45, 0.30, 0.16}, {0.68, 0.50, 0.30},
                             0.05, Vector3d(0, 1, 0.05));
  const int concrete = b.Plain({0.62, 0.62, 0.60});
  const int annex_wall = b.Plain({0.70, 0.72, 0.76});
  const int annex_window =
      b.Pattern(TexturePattern::kChecker, {0.12, 0.14, 0.18}, {0.55, 0.60, 0.65}, 0.25);

  // Ground.
  b.Add(MakeQuad({0, 0, 0}, ex, ey, 60, 60, paving), false);

  // Main façade at y = 12, facing -y; 28 m wide, 10 m tall, three storeys of windows.
  {
    const double half_u = 14, half_v = 5.0;
    std::vector<Opening> openings;
    for (double u : {-10.5, -6.5, -2.5, 2.5, 6.5, 10.5}) {
      for (double floor_z : {2.1, 5.1, 8.1}) {
        const double v = floor_z - half_v;
        openings.push_back({u - 0.7, v - 0.9, u + 0.7, v + 0.9, true});
      }
    }
    openings.push_back({-0.9, -half_v, 0.9, 2.6 - half_v, false});  // door
    AddWallWithOpenings(&b, {0, 12, half_v}, ex, ez, ey, half_u, half_v, openings, 0.25, main_mat);
  }
  // Side wing at x = -14, facing +x, from y = -6 to 12, 9 m tall.
  {
    const double half_u = 9, half_v = 4.5;
    std::vector<Opening> openings;
    for (double u : {-5.0, -1.0, 3.0}) {
      for (double floor_z : {2.2, 5.8}) {
        const double v = floor_z - half_v;
        openings.push_back({u - 0.7, v - 0.9, u + 0.7, v + 0.9, true});
      }
    }
    // Local u runs towards -y so that (u, v, inward) stays right-handed.
    AddWallWithOpenings(&b, {-14, 3, half_v}, -ey, ez, -ex, half_u, half_v, openings, 0.25,
                        side_mat);
  }
  // Low annex on the right: a plain box with flat textured window panels.
  b.Add(MakeBox({8, -2, 0}, {16, 8, 4.5}, annex_wall));
  for (double y : {0.0, 3.0, 6.0}) {
    b.Add(MakeBox({7.97, y - 0.6, 1.2}, {8.0, y + 0.6, 2.6}, annex_window));
  }
  // Street furniture: thin poles with lamp heads, a tree, a bench, a plain planter.
  for (const Vector3d& base : {Vector3d(-5, 4, 0), Vector3d(3, 5, 0), Vector3d(-9.5, 8, 0)}) {
    b.Add(MakeCylinder(base, ez, 0.07, 4.5, metal));
    b.Add(MakeSphere(base + Vector3d(0, 0, 4.6), 0.22, lamp));
  }
  b.Add(MakeCylinder({5.5, 7.5, 0}, ez, 0.2, 3.0, bark));
  b.Add(MakeSphere({5.5, 7.5, 4.2}, 1.6, leaves));
  b.Add(MakeBox({-3, 6.5, 0.42}, {-1, 7.0, 0.5}, wood));
  for (double x : {-2.9, -1.1}) b.Add(MakeBox({x - 0.05, 6.55, 0}, {x + 0.05, 6.95, 0.42}, metal));
  b.Add(MakeBox({0.8, 8.5, 0}, {2.8, 9.5, 0.8}, concrete));

  SyntheticWorld& w = b.world();
  w.lighting.ambient = 0.35;
  w.lighting.sun_direction = Vector3d(-0.4, 0.6, -0.7);
  w.lighting.sun_intensity = 0.7;
  w.lighting.exposure = 0.9;
  w.background.sky = true;
  w.background.color = Vector3d(0.78, 0.84, 0.92);
  w.background.zenith = Vector3d(0.40, 0.56, 0.85);
  w.background.up = ez;
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  double fx, fy, cx, cy;
  Intrinsics(p, &fx, &fy, &cx, &cy);
  SynthRng rng(SynthHash(p.seed, 0xfacade5ULL));
  const int n = p.num_views;
  const double span = std::min(10.0, 1.5 * (n - 1));
  for (int i = 0; i < n; ++i) {
    const double a = Spread(i, n);
    const Vector3d center(a * span + rng.Uniform(-0.2, 0.2), -3.5 + 0.6 * (i % 2),
                          1.6 + rng.Uniform(-0.15, 0.15));
    // Aimed a little above mid-height so that sky (no surface, no GT) shows above the roof.
    const Vector3d target(0.45 * center.x() + rng.Uniform(-1, 1) - 1.5, 12,
                          4.6 + rng.Uniform(-0.6, 0.6));
    const double roll = rng.Uniform(-5, 5) * kDegToRad;
    layout.cameras.push_back(
        LookAtCamera(center, target, ez, roll, p.width, p.height, fx, fy, cx, cy));
  }
  return layout;
}

// A camera centre on a sphere around the origin, looking along +y at azimuth 0 (the plane
// scenes' walls lie in y = 0 and are seen from y < 0).
Vector3d OrbitCenter(double distance, double azimuth, double elevation) {
  return distance * Vector3d(std::sin(azimuth) * std::cos(elevation), -std::cos(azimuth) * std::cos(elevation),
                             std::sin(elevation));
}

SyntheticLayout BuildPlane(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  const int mat = b.Pattern(TexturePattern::kMixed, {0.16, 0.13, 0.10}, {0.92, 0.88, 0.78}, 0.08);
  // The plane faces -y before tilting; tilting turns its normal upwards about the x axis.
  // Cameras sit at or below the plane centre's height, so each optical axis meets the
  // plane at least plane_tilt_deg obliquely.
  const double tilt = p.plane_tilt_deg * kDegToRad;
  const Vector3d normal(0, -std::cos(tilt), std::sin(tilt));
  const Vector3d u = Vector3d::UnitX();
  const Vector3d v = normal.cross(u);
  b.Add(MakeQuad(Vector3d::Zero(), u, v, 8, 8, mat));

  SyntheticWorld& w = b.world();
  w.lighting.ambient = 0.4;
  w.lighting.sun_direction = Vector3d(0.3, 0.5, -0.8);
  w.lighting.sun_intensity = 0.6;
  w.lighting.exposure = 0.95;
  w.background.color = Vector3d(0.3, 0.3, 0.3);
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  double fx, fy, cx, cy;
  Intrinsics(p, &fx, &fy, &cx, &cy);
  SynthRng rng(SynthHash(p.seed, 0x91a4eULL));
  const int n = p.num_views;
  const double distance = 3.0;
  for (int i = 0; i < n; ++i) {
    const double azimuth = (Spread(i, n) * 24.0 + rng.Uniform(-1, 1)) * kDegToRad;
    const double elevation = -rng.Uniform(0.5, 5.0) * kDegToRad;
    const Vector3d center = OrbitCenter(distance, azimuth, elevation);
    const double roll = rng.Uniform(-6, 6) * kDegToRad;
    SyntheticCamera cam = LookAtCamera(center, Vector3d::Zero(), Vector3d::UnitZ(), roll,
                                       p.width, p.height, fx, fy, cx, cy);
    const Vector3d axis = cam.R.row(2).transpose();
    layout.plane_view_angles_deg.push_back(std::acos(std::abs(axis.dot(normal))) / kDegToRad);
    layout.cameras.push_back(cam);
  }
  return layout;
}

// A plain wall lit by a lamp in front of it (smooth shading, no texture) inside a frame of
// textured posters on the same plane, two textured boxes standing in front: the planar
// prior's case, where only the frame and the boxes can be matched.
SyntheticLayout BuildPlainWall(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  const int plain = b.Plain({0.78, 0.76, 0.72});
  const int poster = b.Pattern(TexturePattern::kMixed, {0.15, 0.2, 0.45}, {0.9, 0.85, 0.7}, 0.06);
  const int box = b.Pattern(TexturePattern::kStripes, {0.5, 0.25, 0.15}, {0.9, 0.8, 0.5}, 0.05);
  // The wall is the plane y = 0 seen from y < 0; the frame lies 1 mm in front of it.
  const Vector3d u = Vector3d::UnitX(), v = Vector3d::UnitZ();
  b.Add(MakeQuad(Vector3d::Zero(), u, v, 3.0, 2.0, plain));
  const double f = -0.001;
  b.Add(MakeQuad(Vector3d(0, f, 0.95), u, v, 1.4, 0.18, poster));    // top
  b.Add(MakeQuad(Vector3d(0, f, -0.95), u, v, 1.4, 0.18, poster));   // bottom
  b.Add(MakeQuad(Vector3d(-1.22, f, 0), u, v, 0.18, 0.77, poster));  // left
  b.Add(MakeQuad(Vector3d(1.22, f, 0), u, v, 0.18, 0.77, poster));   // right
  b.Add(MakeBox(Vector3d(-0.9, -0.9, -1.15), Vector3d(-0.5, -0.5, -0.75), box));
  b.Add(MakeBox(Vector3d(0.5, -0.75, -1.15), Vector3d(0.9, -0.35, -0.75), box));

  SyntheticWorld& w = b.world();
  w.lighting.ambient = 0.25;
  w.lighting.sun_intensity = 0.0;
  w.lighting.has_point_light = true;
  w.lighting.point_position = Vector3d(-0.8, -1.8, 1.1);
  w.lighting.point_power = 2.5;
  w.lighting.point_softness = 0.5;
  w.lighting.exposure = 0.9;
  w.background.color = Vector3d(0.3, 0.3, 0.3);
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  double fx, fy, cx, cy;
  Intrinsics(p, &fx, &fy, &cx, &cy);
  SynthRng rng(SynthHash(p.seed, 0x3a11ULL));
  for (int i = 0; i < p.num_views; ++i) {
    const double azimuth = (Spread(i, p.num_views) * 40.0 + rng.Uniform(-1, 1)) * kDegToRad;
    const double elevation = rng.Uniform(-3.0, 3.0) * kDegToRad;
    const double distance = 3.0;
    const Vector3d center = OrbitCenter(distance, azimuth, elevation);
    const Vector3d target(rng.Uniform(-0.1, 0.1), 0, rng.Uniform(-0.1, 0.1));
    layout.cameras.push_back(LookAtCamera(center, target, Vector3d::UnitZ(), rng.Uniform(-3, 3) * kDegToRad,
                                          p.width, p.height, fx, fy, cx, cy));
  }
  return layout;
}

}  // namespace

std::vector<std::string> SyntheticLayoutNames() {
  std::vector<std::string> names = {"indoor", "facade", "plane", "plain_wall"};
  for (const std::string& room : RoomLayoutNames()) names.push_back(room);
  return names;
}

std::string SyntheticLayoutNameList() {
  std::string list;
  for (const std::string& name : SyntheticLayoutNames()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

SyntheticLayout BuildSyntheticLayout(const LayoutParams& params) {
  if (params.scene == "indoor") return BuildIndoor(params);
  if (params.scene == "facade") return BuildFacade(params);
  if (params.scene == "plane") return BuildPlane(params);
  if (params.scene == "plain_wall") return BuildPlainWall(params);
  if (IsRoomLayout(params.scene)) return BuildRoomLayout(params);
  throw Error("unknown synthetic scene '" + params.scene + "' (valid: " + SyntheticLayoutNameList() +
              ")");
}

}  // namespace mpmvs
