#include "colmap_ext/synthetic/room_layouts.h"

#include <algorithm>
#include <cmath>

#include "colmap_ext/synthetic/world_builder.h"
#include "colmap_ext/util/error.h"

namespace mpmvs {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

const Vector3d kEx = Vector3d::UnitX(), kEy = Vector3d::UnitY(), kEz = Vector3d::UnitZ();

struct Intrinsics {
  double fx, fy, cx, cy;
};

// f = 512 px at 640 x 480 (~64 degree horizontal field of view); fy differs slightly from fx
// and the principal point is off-centre so that mixing them up shows.
Intrinsics RoomIntrinsics(const LayoutParams& p) {
  Intrinsics k;
  k.fx = 0.8 * p.width;
  k.fy = 1.002 * k.fx;
  k.cx = 0.5 * p.width + 0.008 * p.width;
  k.cy = 0.5 * p.height - 0.006 * p.height;
  return k;
}

SyntheticCamera RoomCamera(const LayoutParams& p, const Vector3d& center, const Vector3d& target,
                           double roll_deg) {
  const Intrinsics k = RoomIntrinsics(p);
  return LookAtCamera(center, target, kEz, roll_deg * kDegToRad, p.width, p.height, k.fx, k.fy,
                      k.cx, k.cy);
}

// Vertical wall from floor point a to floor point b (z in [0, height]); a room shell part:
// it casts no shadow so that lamps inside light the whole room.
void AddWall(WorldBuilder* b, const Vector2d& a, const Vector2d& c, double height, int material) {
  const Vector2d mid = 0.5 * (a + c);
  const Vector2d d = c - a;
  b->Add(MakeQuad(Vector3d(mid.x(), mid.y(), 0.5 * height), Vector3d(d.x(), d.y(), 0), kEz,
                  0.5 * d.norm(), 0.5 * height, material),
         false);
}

// Closed outline of walls through the floor-plan points (in order).
void AddWalls(WorldBuilder* b, const std::vector<Vector2d>& outline, double height,
              const std::vector<int>& materials) {
  for (size_t i = 0; i < outline.size(); ++i) {
    AddWall(b, outline[i], outline[(i + 1) % outline.size()], height, materials[i]);
  }
}

// Horizontal rectangle [x0,x1] x [y0,y1] at height z (floor or ceiling part).
void AddHorizontal(WorldBuilder* b, double x0, double y0, double x1, double y1, double z,
                   int material) {
  b->Add(MakeQuad(Vector3d(0.5 * (x0 + x1), 0.5 * (y0 + y1), z), kEx, kEy, 0.5 * (x1 - x0),
                  0.5 * (y1 - y0), material),
         false);
}

ScenePointLight Lamp(const Vector3d& position, double power, double softness) {
  ScenePointLight l;
  l.position = position;
  l.power = power;
  l.softness = softness;
  return l;
}

// Lighting shared by the rooms: a soft ambient term, a weak directional fill, lamps.
void SetRoomLighting(SyntheticWorld* w, const std::vector<ScenePointLight>& lamps,
                     const Vector3d& fill_direction, double fill, double ambient, double exposure) {
  w->lighting.ambient = ambient;
  w->lighting.sun_direction = fill_direction;
  w->lighting.sun_intensity = fill;
  w->lighting.has_point_light = true;
  w->lighting.point_position = lamps[0].position;
  w->lighting.point_power = lamps[0].power;
  w->lighting.point_softness = lamps[0].softness;
  w->lighting.extra_point_lights.assign(lamps.begin() + 1, lamps.end());
  w->lighting.exposure = exposure;
  w->background.color = Vector3d(0, 0, 0);  // unreachable: the rooms are closed
}

// The room shell's surfaces as scored on their own (gt/surface_<stem>.png).
void NameShell(WorldBuilder* b, const std::vector<int>& walls, int ceiling, const std::vector<int>& floors) {
  for (int m : walls) b->NameSurface(m, "walls");
  b->NameSurface(ceiling, "ceiling");
  for (int m : floors) b->NameSurface(m, "floor");
}

// Thin vertical pole with horizontal stripes and a lamp shade or cap on top.
void AddStripedPole(WorldBuilder* b, const Vector3d& base, double height, int pole, int cap) {
  b->Add(MakeCylinder(base, kEz, 0.02, height, pole));
  b->Add(MakeCylinder(base + height * kEz, kEz, 0.16, 0.24, cap));
}

SyntheticLayout BuildRoomWindow(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  // Box room x in [-2.5, 2.5], y in [-2, 2], z in [0, 2.6]; the window wall is y = 2.
  const double X = 2.5, Y = 2.0, H = 2.6;
  const int paint = b.Plain({0.82, 0.80, 0.76});
  const int ceiling = b.Plain({0.88, 0.88, 0.87});
  const int carpet = b.Plain({0.46, 0.42, 0.38});
  NameShell(&b, {paint}, ceiling, {carpet});
  const int frame = b.Plain({0.93, 0.93, 0.91});
  SurfaceMaterial glow;
  glow.color_a = Vector3d(0.9, 0.9, 0.9);
  glow.emission = Vector3d(1.25, 1.30, 1.40);  // over-exposed daylight: clips near 255
  const int window = b.AddMaterial(glow);
  AddWalls(&b, {{-X, -Y}, {X, -Y}, {X, Y}, {-X, Y}}, H, {paint, paint, paint, paint});
  AddHorizontal(&b, -X, -Y, X, Y, 0, carpet);
  AddHorizontal(&b, -X, -Y, X, Y, H, ceiling);

  // The window: an emissive pane flush with the wall, a plain frame and mullion cross.
  const Vector3d wc(0.4, Y - 0.004, 1.45);
  const double wu = 0.8, wv = 0.6;
  b.Add(MakeQuad(wc, kEx, kEz, wu, wv, window));
  const double t = 0.04, d = 0.05;
  b.Add(MakeBox(wc + Vector3d(-wu - t, -d, -wv - t), wc + Vector3d(wu + t, 0, -wv), frame));
  b.Add(MakeBox(wc + Vector3d(-wu - t, -d, wv), wc + Vector3d(wu + t, 0, wv + t), frame));
  b.Add(MakeBox(wc + Vector3d(-wu - t, -d, -wv), wc + Vector3d(-wu, 0, wv), frame));
  b.Add(MakeBox(wc + Vector3d(wu, -d, -wv), wc + Vector3d(wu + t, 0, wv), frame));
  b.Add(MakeBox(wc + Vector3d(-0.02, -d, -wv), wc + Vector3d(0.02, 0, wv), frame));
  b.Add(MakeBox(wc + Vector3d(-wu, -d, 0.12), wc + Vector3d(wu, 0, 0.16), frame));
  b.Add(MakeBox(wc + Vector3d(-wu - 0.1, -0.16, -wv - t - 0.04), wc + Vector3d(wu + 0.1, 0, -wv - t),
                frame));  // sill

  const int curtain = b.Pattern(TexturePattern::kStripes, {0.55, 0.20, 0.18}, {0.85, 0.70, 0.55},
                                0.07, kEx);
  const int books = b.Pattern(TexturePattern::kStripes, {0.55, 0.15, 0.12}, {0.20, 0.35, 0.60},
                              0.04, Vector3d(1, 0.2, 0));
  const int pot = b.Pattern(TexturePattern::kNoise, {0.55, 0.28, 0.16}, {0.80, 0.50, 0.32}, 0.05);
  const int leaves = b.Pattern(TexturePattern::kNoise, {0.10, 0.30, 0.08}, {0.45, 0.62, 0.20}, 0.08);
  const int cloth = b.Pattern(TexturePattern::kMixed, {0.15, 0.25, 0.50}, {0.85, 0.85, 0.90}, 0.07);
  const int rug = b.Pattern(TexturePattern::kMixed, {0.60, 0.22, 0.16}, {0.92, 0.82, 0.52}, 0.12);
  const int poster = b.Pattern(TexturePattern::kNoise, {0.10, 0.28, 0.58}, {0.95, 0.90, 0.72}, 0.09);
  const int picture = b.Pattern(TexturePattern::kChecker, {0.14, 0.14, 0.16}, {0.90, 0.88, 0.80}, 0.08);
  const int pole = b.Pattern(TexturePattern::kStripes, {0.10, 0.10, 0.12}, {0.92, 0.90, 0.30},
                             0.05, kEz);
  const int shade = b.Pattern(TexturePattern::kNoise, {0.85, 0.80, 0.65}, {0.55, 0.45, 0.30}, 0.04);
  const int wood = b.Pattern(TexturePattern::kStripes, {0.42, 0.26, 0.14}, {0.72, 0.52, 0.32},
                             0.05, Vector3d(0.2, 0.1, 1.0));

  b.Add(MakeQuad({-0.62, Y - 0.06, 1.25}, kEx, kEz, 0.2, 1.05, curtain));
  b.Add(MakeBox({-2.45, 1.50, 0}, {-1.55, 1.98, 1.95}, books));            // bookshelf
  b.Add(MakeCylinder({2.05, 1.55, 0}, kEz, 0.22, 0.45, pot));               // plant
  b.Add(MakeSphere({2.05, 1.55, 0.92}, 0.42, leaves));
  b.Add(MakeYawedBox({2.0, -0.2, 0.25}, {0.42, 0.42, 0.25}, 0.35, cloth));  // armchair
  b.Add(MakeYawedBox({2.25, -0.1, 0.65}, {0.12, 0.42, 0.2}, 0.35, cloth));
  b.Add(MakeQuad({0.0, 0.3, 0.004}, kEx, kEy, 0.9, 0.6, rug));
  b.Add(MakeQuad({-X + 0.01, 0.2, 1.5}, kEy, kEz, 0.45, 0.32, poster));
  b.Add(MakeQuad({X - 0.01, 1.0, 1.6}, kEy, kEz, 0.3, 0.25, picture));
  b.Add(MakeBox({-1.45, 1.55, 0}, {-0.95, 1.95, 0.55}, wood));             // side table
  AddStripedPole(&b, {-2.1, -0.4, 0}, 1.55, pole, shade);

  SyntheticWorld& w = b.world();
  SetRoomLighting(&w, {Lamp({-0.3, -0.2, 2.15}, 1.1, 0.9), Lamp({2.1, -1.3, 1.5}, 0.35, 0.5)},
                  Vector3d(0.15, -0.8, -0.55), 0.18, 0.30, 0.85);
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  SynthRng rng(SynthHash(p.seed, 0x3007a7cULL));
  const Vector2d arc_center(0.0, 0.5);
  const int n = p.num_views;
  for (int i = 0; i < n; ++i) {
    const double theta = (-90.0 + 100.0 * Spread(i, n) + rng.Uniform(-2, 2)) * kDegToRad;
    const Vector2d radial(std::cos(theta), std::sin(theta));
    const Vector2d c = arc_center + 1.9 * radial;
    const double z = 1.5 + 0.1 * ((i % 3) - 1) + rng.Uniform(-0.03, 0.03);
    const Vector2d look = arc_center - 1.6 * radial;
    const double target_z = (i % 2 ? 1.95 : 1.15) + rng.Uniform(-0.1, 0.1);
    layout.cameras.push_back(RoomCamera(p, Vector3d(c.x(), c.y(), z),
                                        Vector3d(look.x(), look.y(), target_z),
                                        rng.Uniform(-4, 4)));
  }
  return layout;
}

SyntheticLayout BuildRoomL(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  // Wing A: x in [0, 7], y in [0, 3.2]; wing B: x in [0, 3.2], y in [3.2, 7.5]; 2.7 m high.
  const double H = 2.7;
  const int paint = b.Plain({0.80, 0.79, 0.75});
  const int accent = b.Plain({0.70, 0.75, 0.80});
  const int ceiling = b.Plain({0.88, 0.88, 0.87});
  // Polished concrete: a textured material, but its contrast is only a few grey levels.
  const int concrete =
      b.Pattern(TexturePattern::kNoise, {0.50, 0.48, 0.45}, {0.545, 0.525, 0.495}, 0.45);
  NameShell(&b, {paint, accent}, ceiling, {concrete});
  AddWalls(&b, {{0, 0}, {7, 0}, {7, 3.2}, {3.2, 3.2}, {3.2, 7.5}, {0, 7.5}}, H,
           {paint, paint, paint, accent, paint, paint});
  AddHorizontal(&b, 0, 0, 7, 3.2, 0, concrete);
  AddHorizontal(&b, 0, 3.2, 3.2, 7.5, 0, concrete);
  AddHorizontal(&b, 0, 0, 7, 3.2, H, ceiling);
  AddHorizontal(&b, 0, 3.2, 3.2, 7.5, H, ceiling);

  const int cloth = b.Pattern(TexturePattern::kMixed, {0.45, 0.18, 0.12}, {0.90, 0.80, 0.60}, 0.07);
  const int wood = b.Pattern(TexturePattern::kStripes, {0.42, 0.26, 0.14}, {0.72, 0.52, 0.32},
                             0.05, Vector3d(1.0, 0.1, 0.2));
  const int metal = b.Pattern(TexturePattern::kNoise, {0.20, 0.20, 0.22}, {0.70, 0.70, 0.72}, 0.03);
  const int picture = b.Pattern(TexturePattern::kMixed, {0.20, 0.45, 0.25}, {0.90, 0.85, 0.60}, 0.07);
  const int poster = b.Pattern(TexturePattern::kNoise, {0.10, 0.28, 0.58}, {0.95, 0.90, 0.72}, 0.09);
  const int poster2 = b.Pattern(TexturePattern::kChecker, {0.14, 0.14, 0.16}, {0.90, 0.88, 0.80}, 0.07);
  const int books = b.Pattern(TexturePattern::kStripes, {0.55, 0.15, 0.12}, {0.20, 0.35, 0.60},
                              0.035, Vector3d(1, 0, 0.3));
  const int crate = b.Pattern(TexturePattern::kChecker, {0.70, 0.55, 0.30}, {0.35, 0.22, 0.10}, 0.06);
  const int pole = b.Pattern(TexturePattern::kStripes, {0.85, 0.12, 0.10}, {0.92, 0.92, 0.90},
                             0.06, kEz);
  const int shade = b.Pattern(TexturePattern::kNoise, {0.85, 0.80, 0.65}, {0.55, 0.45, 0.30}, 0.04);
  const int pot = b.Pattern(TexturePattern::kNoise, {0.55, 0.28, 0.16}, {0.80, 0.50, 0.32}, 0.05);
  const int leaves = b.Pattern(TexturePattern::kNoise, {0.10, 0.30, 0.08}, {0.45, 0.62, 0.20}, 0.08);

  b.Add(MakeBox({4.0, 2.35, 0}, {6.0, 3.15, 0.45}, cloth));  // sofa against the inner wall
  b.Add(MakeBox({4.0, 2.85, 0.45}, {6.0, 3.15, 0.85}, cloth));
  b.Add(MakeBox({4.4, 1.45, 0.38}, {5.6, 1.95, 0.43}, wood));  // coffee table
  for (double x : {4.47, 5.53}) {
    for (double y : {1.52, 1.88}) b.Add(MakeCylinder({x, y, 0}, kEz, 0.025, 0.38, metal));
  }
  b.Add(MakeQuad({6.99, 1.6, 1.5}, kEy, kEz, 0.6, 0.4, picture));
  b.Add(MakeQuad({5.0, 3.19, 1.65}, kEx, kEz, 0.55, 0.3, poster2));
  b.Add(MakeQuad({3.19, 5.1, 1.5}, kEy, kEz, 0.4, 0.55, poster));
  b.Add(MakeBox({0.3, 7.05, 0}, {1.5, 7.45, 1.9}, books));  // bookshelf on the end wall
  b.Add(MakeBox({0.05, 1.3, 0}, {0.5, 2.7, 0.85}, wood));   // sideboard in wing A
  b.Add(MakeBox({0.1, 1.5, 0.85}, {0.4, 1.9, 1.1}, books));
  b.Add(MakeQuad({0.01, 2.0, 1.65}, kEy, kEz, 0.5, 0.35, picture));
  b.Add(MakeYawedBox({2.2, 1.9, 0.2}, {0.3, 0.3, 0.2}, 0.4, cloth));  // ottoman
  b.Add(MakeBox({2.1, 6.75, 0}, {3.0, 7.4, 0.5}, crate));
  b.Add(MakeYawedBox({2.5, 7.05, 0.72}, {0.25, 0.22, 0.22}, 0.3, crate));
  b.Add(MakeCylinder({3.55, 2.75, 0}, kEz, 0.2, 0.4, pot));
  b.Add(MakeSphere({3.55, 2.75, 0.78}, 0.36, leaves));
  AddStripedPole(&b, {2.75, 3.7, 0}, 1.7, pole, shade);

  SyntheticWorld& w = b.world();
  SetRoomLighting(&w, {Lamp({5.0, 1.6, 2.3}, 1.0, 0.9), Lamp({1.6, 5.4, 2.3}, 1.0, 0.9)},
                  Vector3d(0.3, 0.5, -0.8), 0.12, 0.30, 0.85);
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  SynthRng rng(SynthHash(p.seed, 0x1a0b0e1ULL));
  // Path along the outer walls: west along y = 0.6, then north along x = 0.6, looking
  // diagonally across the room and mostly down at the floor. The heading turns smoothly
  // over 3 m around the corner so neighbouring views keep overlapping.
  const Vector2d p0(5.7, 0.6), corner(0.6, 0.6), p1(0.6, 5.4);
  const double leg1 = (corner - p0).norm(), leg2 = (p1 - corner).norm();
  const Vector2d look1 = Vector2d(-0.62, 0.78).normalized(), look2 = Vector2d(0.85, 0.5).normalized();
  const int n = p.num_views;
  for (int i = 0; i < n; ++i) {
    const double s = (Spread(i, n) + 0.5) * (leg1 + leg2);
    const Vector2d c = s <= leg1 ? p0 + s * (corner - p0) / leg1
                                 : corner + (s - leg1) * (p1 - corner) / leg2;
    const double wgt = std::min(1.0, std::max(0.0, (s - (leg1 - 1.5)) / 3.0));
    const double yaw = rng.Uniform(-5, 5) * kDegToRad;
    Vector2d look = ((1 - wgt) * look1 + wgt * look2).normalized();
    look = Vector2d(std::cos(yaw) * look.x() - std::sin(yaw) * look.y(),
                    std::sin(yaw) * look.x() + std::cos(yaw) * look.y());
    const Vector2d c2 = c + Vector2d(rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1));
    const double z = 1.6 + rng.Uniform(-0.08, 0.08);
    const double pitch = ((i % 3 == 1) ? -4.0 : -17.0) + rng.Uniform(-2, 2);
    const Vector3d dir(look.x(), look.y(), std::tan(pitch * kDegToRad));
    const Vector3d center(c2.x(), c2.y(), z);
    layout.cameras.push_back(RoomCamera(p, center, center + 3.0 * dir, rng.Uniform(-4, 4)));
  }
  return layout;
}

SyntheticLayout BuildRoomCorridor(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  // Corridor x in [-1, 1], y in [0, 10]; side branch x in [1, 7], y in [8, 10]; 2.5 m high.
  const double H = 2.5;
  const int paint = b.Plain({0.76, 0.80, 0.74});
  const int ceiling = b.Plain({0.90, 0.90, 0.89});
  const int tiles = b.Pattern(TexturePattern::kChecker, {0.46, 0.44, 0.41}, {0.62, 0.60, 0.56}, 0.4);
  NameShell(&b, {paint}, ceiling, {tiles});
  AddWalls(&b, {{-1, 0}, {1, 0}, {1, 8}, {7, 8}, {7, 10}, {-1, 10}}, H,
           {paint, paint, paint, paint, paint, paint});
  AddHorizontal(&b, -1, 0, 1, 10, 0, tiles);
  AddHorizontal(&b, 1, 8, 7, 10, 0, tiles);
  AddHorizontal(&b, -1, 0, 1, 10, H, ceiling);
  AddHorizontal(&b, 1, 8, 7, 10, H, ceiling);

  // Lamp panels: plain emissive boxes under the ceiling, each above a point light.
  SurfaceMaterial panel_material;
  panel_material.color_a = Vector3d(0.9, 0.9, 0.9);
  panel_material.emission = Vector3d(0.95, 0.95, 0.92);
  const int panel = b.AddMaterial(panel_material);
  const std::vector<Vector3d> lamp_xy = {{0, 1.8, 0}, {0, 5.0, 0}, {0, 8.6, 0}, {4.2, 9.0, 0}};
  std::vector<ScenePointLight> lamps;
  for (const Vector3d& l : lamp_xy) {
    const bool along_x = l.x() > 1;
    const Vector3d half = along_x ? Vector3d(0.3, 0.15, 0.02) : Vector3d(0.15, 0.3, 0.02);
    b.Add(MakeBox(Vector3d(l.x(), l.y(), H) - half - Vector3d(0, 0, 0.02),
                  Vector3d(l.x(), l.y(), H) + half - Vector3d(0, 0, 0.02), panel),
          false);
    lamps.push_back(Lamp(Vector3d(l.x(), l.y(), H - 0.25), 0.55, 0.7));
  }

  const int door = b.Pattern(TexturePattern::kStripes, {0.42, 0.28, 0.16}, {0.66, 0.48, 0.30},
                             0.045, Vector3d(0.05, 0.1, 1.0));
  const int metal = b.Pattern(TexturePattern::kNoise, {0.20, 0.20, 0.22}, {0.70, 0.70, 0.72}, 0.03);
  const int notice = b.Pattern(TexturePattern::kNoise, {0.10, 0.28, 0.58}, {0.95, 0.90, 0.72}, 0.06);
  const int map = b.Pattern(TexturePattern::kMixed, {0.20, 0.45, 0.25}, {0.90, 0.85, 0.60}, 0.06);
  const int red = b.Pattern(TexturePattern::kNoise, {0.55, 0.06, 0.05}, {0.90, 0.25, 0.15}, 0.03);
  const int radiator = b.Pattern(TexturePattern::kStripes, {0.55, 0.55, 0.55}, {0.92, 0.92, 0.90},
                                 0.04, kEy);
  const int pole = b.Pattern(TexturePattern::kStripes, {0.90, 0.75, 0.10}, {0.10, 0.10, 0.10},
                             0.08, kEz);
  const int cap = b.Pattern(TexturePattern::kNoise, {0.12, 0.12, 0.14}, {0.45, 0.45, 0.48}, 0.04);
  const int bench = b.Pattern(TexturePattern::kStripes, {0.45, 0.30, 0.16}, {0.68, 0.50, 0.30},
                              0.05, kEx);
  const int poster = b.Pattern(TexturePattern::kChecker, {0.14, 0.14, 0.16}, {0.90, 0.88, 0.80}, 0.07);

  for (double y : {2.8, 6.6}) {  // doors on the left wall, one on the right
    b.Add(MakeQuad({-0.995, y, 1.0}, kEy, kEz, 0.45, 1.0, door));
    b.Add(MakeCylinder({-0.99, y + 0.33, 1.0}, kEx, 0.02, 0.07, metal));
  }
  b.Add(MakeQuad({0.995, 4.6, 1.0}, kEy, kEz, 0.45, 1.0, door));
  b.Add(MakeCylinder({0.92, 4.27, 1.0}, kEx, 0.02, 0.07, metal));
  b.Add(MakeQuad({0.995, 2.0, 1.5}, kEy, kEz, 0.45, 0.32, notice));
  b.Add(MakeQuad({0.0, 9.99, 1.45}, kEx, kEz, 0.55, 0.4, map));
  b.Add(MakeQuad({6.99, 9.0, 1.5}, kEy, kEz, 0.5, 0.4, poster));
  b.Add(MakeBox({-0.99, 4.2, 0.15}, {-0.92, 5.2, 0.75}, radiator));
  b.Add(MakeCylinder({0.85, 6.3, 0}, kEz, 0.08, 0.5, red));  // extinguisher
  b.Add(MakeQuad({4.6, 8.005, 1.0}, kEx, kEz, 0.45, 1.0, door));  // in the branch
  b.Add(MakeQuad({2.2, 9.995, 1.5}, kEx, kEz, 0.45, 0.32, notice));
  b.Add(MakeBox({3.0, 9.55, 0.42}, {5.0, 9.95, 0.48}, bench));
  for (double x : {3.1, 4.9}) b.Add(MakeBox({x - 0.04, 9.6, 0}, {x + 0.04, 9.9, 0.42}, metal));
  AddStripedPole(&b, {0.55, 8.5, 0}, 1.0, pole, cap);

  SyntheticWorld& w = b.world();
  SetRoomLighting(&w, lamps, Vector3d(0.2, 0.4, -0.9), 0.10, 0.30, 0.85);
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  SynthRng rng(SynthHash(p.seed, 0xc0441d0ULL));
  const int n = p.num_views;
  // Walk forward up the corridor, then turn right into the branch over the last views.
  const int turning = std::max(2, std::min(4, n / 3));
  const int walking = n - turning;
  for (int i = 0; i < n; ++i) {
    Vector2d c;
    double yaw_deg;  // 0 = +y, positive towards +x
    if (i < walking) {
      const double a = walking > 1 ? static_cast<double>(i) / (walking - 1) : 0.0;
      c = Vector2d(-0.2 + 0.15 * std::sin(2.1 * i), 0.6 + a * 6.4);
      yaw_deg = 6.0 * std::sin(1.3 * i + 0.4);
    } else {
      const double a = static_cast<double>(i - walking + 1) / turning;
      c = Vector2d(-0.1 + 0.5 * a, 7.6 + 1.4 * a);
      yaw_deg = 20.0 + 65.0 * a;
    }
    yaw_deg += rng.Uniform(-2, 2);
    const double yaw = yaw_deg * kDegToRad;
    const double pitch = ((i % 3 == 2) ? 4.0 : -6.0) + rng.Uniform(-2, 2);
    const Vector3d dir(std::sin(yaw), std::cos(yaw), std::tan(pitch * kDegToRad));
    const Vector3d center(c.x(), c.y(), 1.6 + rng.Uniform(-0.06, 0.06));
    layout.cameras.push_back(RoomCamera(p, center, center + 3.0 * dir, rng.Uniform(-3, 3)));
  }
  return layout;
}

SyntheticLayout BuildRoomSweep(const LayoutParams& p) {
  WorldBuilder b(p.seed);
  // Long hall x in [-2.2, 2.2], y in [0, 9], z in [0, 2.6]; the far wall is y = 9. The
  // cameras translate across it near y = 0.9 facing the far wall, so the side walls (and
  // floor and ceiling) are seen at 60-85 degrees of incidence.
  const double X = 2.2, Y = 9.0, H = 2.6;
  const int side = b.Plain({0.80, 0.79, 0.75});
  const int far_wall = b.Plain({0.78, 0.80, 0.82});
  const int back = b.Plain({0.80, 0.79, 0.75});
  const int ceiling = b.Plain({0.88, 0.88, 0.87});
  const int floor = b.Plain({0.52, 0.47, 0.41});
  b.NameSurface(side, "side walls");
  b.NameSurface(far_wall, "far wall");
  b.NameSurface(back, "walls");
  b.NameSurface(ceiling, "ceiling");
  b.NameSurface(floor, "floor");
  AddWalls(&b, {{-X, 0}, {X, 0}, {X, Y}, {-X, Y}}, H, {back, side, far_wall, side});
  AddHorizontal(&b, -X, 0, X, Y, 0, floor);
  AddHorizontal(&b, -X, 0, X, Y, H, ceiling);

  const int books = b.Pattern(TexturePattern::kStripes, {0.55, 0.15, 0.12}, {0.20, 0.35, 0.60},
                              0.04, Vector3d(1, 0.2, 0));
  const int poster = b.Pattern(TexturePattern::kNoise, {0.10, 0.28, 0.58}, {0.95, 0.90, 0.72}, 0.09);
  const int picture = b.Pattern(TexturePattern::kChecker, {0.14, 0.14, 0.16}, {0.90, 0.88, 0.80}, 0.08);
  const int door = b.Pattern(TexturePattern::kStripes, {0.42, 0.28, 0.16}, {0.66, 0.48, 0.30},
                             0.045, Vector3d(0.05, 0.1, 1.0));
  const int cloth = b.Pattern(TexturePattern::kMixed, {0.15, 0.25, 0.50}, {0.85, 0.85, 0.90}, 0.07);
  const int rug = b.Pattern(TexturePattern::kMixed, {0.60, 0.22, 0.16}, {0.92, 0.82, 0.52}, 0.12);
  const int radiator = b.Pattern(TexturePattern::kStripes, {0.55, 0.55, 0.55}, {0.92, 0.92, 0.90},
                                 0.04, kEy);
  const int pot = b.Pattern(TexturePattern::kNoise, {0.55, 0.28, 0.16}, {0.80, 0.50, 0.32}, 0.05);
  const int leaves = b.Pattern(TexturePattern::kNoise, {0.10, 0.30, 0.08}, {0.45, 0.62, 0.20}, 0.08);
  const int pole = b.Pattern(TexturePattern::kStripes, {0.10, 0.10, 0.12}, {0.92, 0.90, 0.30},
                             0.05, kEz);
  const int shade = b.Pattern(TexturePattern::kNoise, {0.85, 0.80, 0.65}, {0.55, 0.45, 0.30}, 0.04);

  b.Add(MakeBox({-2.15, 8.45, 0}, {-1.2, 8.95, 2.0}, books));       // bookshelf, far left corner
  b.Add(MakeQuad({0.5, Y - 0.01, 1.55}, kEx, kEz, 0.55, 0.4, poster));  // on the far wall
  b.Add(MakeQuad({X - 0.005, 3.2, 1.0}, kEy, kEz, 0.45, 1.0, door));  // side walls: little on them
  b.Add(MakeQuad({-X + 0.01, 6.0, 1.55}, kEy, kEz, 0.35, 0.28, picture));
  b.Add(MakeBox({-X + 0.01, 2.4, 0.15}, {-X + 0.08, 3.6, 0.75}, radiator));
  b.Add(MakeBox({1.35, 5.2, 0}, {2.15, 7.0, 0.45}, cloth));         // sofa against the right wall
  b.Add(MakeBox({1.85, 5.2, 0.45}, {2.15, 7.0, 0.85}, cloth));
  b.Add(MakeQuad({-0.2, 5.0, 0.004}, kEx, kEy, 0.9, 1.2, rug));
  b.Add(MakeCylinder({1.8, 8.5, 0}, kEz, 0.22, 0.45, pot));          // plant, far right corner
  b.Add(MakeSphere({1.8, 8.5, 0.92}, 0.42, leaves));
  AddStripedPole(&b, {-1.6, 4.2, 0}, 1.55, pole, shade);

  SyntheticWorld& w = b.world();
  // A ceiling light 12 cm under the ceiling with little softness: its hot spot saturates and
  // falls off steeply over the plain ceiling; a weaker lamp lights the rest of the hall.
  SetRoomLighting(&w, {Lamp({0.3, 4.6, H - 0.12}, 0.5, 0.06), Lamp({0.0, 2.5, 2.0}, 0.8, 0.9)},
                  Vector3d(0.1, 0.6, -0.8), 0.12, 0.30, 0.85);
  w.geometry.Build();

  SyntheticLayout layout;
  layout.world = std::move(b.world());
  SynthRng rng(SynthHash(p.seed, 0x5ee9a11ULL));
  const int n = p.num_views;
  for (int i = 0; i < n; ++i) {
    // Across the hall from left to right, facing the far wall.
    const Vector3d center(3.0 * Spread(i, n) + rng.Uniform(-0.05, 0.05), 0.9 + rng.Uniform(-0.1, 0.1),
                          1.55 + rng.Uniform(-0.06, 0.06));
    const double yaw = rng.Uniform(-4, 4) * kDegToRad;
    const double pitch = ((i % 3 == 1) ? 4.0 : -3.0) + rng.Uniform(-2, 2);
    const Vector3d dir(std::sin(yaw), std::cos(yaw), std::tan(pitch * kDegToRad));
    layout.cameras.push_back(RoomCamera(p, center, center + 3.0 * dir, rng.Uniform(-3, 3)));
  }
  return layout;
}

}  // namespace

std::vector<std::string> RoomLayoutNames() { return {"room_window", "room_l", "room_corridor", "room_sweep"}; }

bool IsRoomLayout(const std::string& name) {
  const std::vector<std::string> names = RoomLayoutNames();
  return std::find(names.begin(), names.end(), name) != names.end();
}

SyntheticLayout BuildRoomLayout(const LayoutParams& params) {
  if (params.scene == "room_window") return BuildRoomWindow(params);
  if (params.scene == "room_l") return BuildRoomL(params);
  if (params.scene == "room_corridor") return BuildRoomCorridor(params);
  if (params.scene == "room_sweep") return BuildRoomSweep(params);
  throw Error("unknown room layout '" + params.scene + "'");
}

}  // namespace mpmvs
