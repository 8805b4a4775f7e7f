#pragma once
// An analytic test scene for the kernels: a textured plane rendered (2x2 supersampling) into
// cameras that look at it, so the true depth and normal of every pixel are known exactly.
// Shared by the CPU-engine and CUDA-backend tests.
#include <cmath>
#include <random>
#include <vector>

#include "kernels/patch_match.h"

namespace mpmvs {
namespace kernels {
namespace test {

struct PlaneScene {
  Vec3 plane_point;
  Vec3 plane_normal;  // world frame, unit length
  std::vector<Camera> cameras;
  std::vector<std::vector<float>> images;  // grey, one per camera
};

// Principal point slightly off-centre so that no code path can rely on W/2, H/2.
inline Camera LookAtCamera(int W, int H, float focal, Vec3 centre, Vec3 target, Vec3 up) {
  Camera cam;
  cam.width = W;
  cam.height = H;
  cam.fx = cam.fy = focal * W;
  cam.cx = W / 2.f - 0.3f;
  cam.cy = H / 2.f + 0.2f;
  const Vec3 z = Normalize(target - centre);
  const Vec3 x = Normalize(Cross(z, up));
  const Vec3 y = Cross(z, x);
  const float R[9] = {x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z};
  for (int i = 0; i < 9; ++i) cam.R[i] = R[i];
  const Vec3 t = -MatVec(cam.R, centre);
  cam.t[0] = t.x, cam.t[1] = t.y, cam.t[2] = t.z;
  return cam;
}

// Renders scene->images from scene->cameras: texture(a, b) on plane coordinates (metres),
// plus Gaussian noise of noise_sigma grey levels (none when 0) drawn from one seeded stream.
template <typename Texture>
void RenderPlaneScene(Texture texture, float noise_sigma, unsigned seed, PlaneScene* scene) {
  const Vec3 n = scene->plane_normal;
  const Vec3 axis_u = Normalize(Cross(n, Vec3{0.f, 1.f, 0.f}));
  const Vec3 axis_v = Cross(n, axis_u);
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.f, noise_sigma > 0.f ? noise_sigma : 1.f);
  scene->images.clear();
  for (const Camera& cam : scene->cameras) {
    const Vec3 C = -MatTVec(cam.R, Vec3{cam.t[0], cam.t[1], cam.t[2]});
    std::vector<float> img(static_cast<size_t>(cam.width) * cam.height);
    for (int v = 0; v < cam.height; ++v) {
      for (int u = 0; u < cam.width; ++u) {
        float acc = 0.f;
        for (int s = 0; s < 4; ++s) {
          const Vec3 dir = MatTVec(cam.R, PixelRay(cam, u - 0.25f + 0.5f * (s & 1), v - 0.25f + 0.5f * (s >> 1)));
          const float lambda = Dot(scene->plane_point - C, n) / Dot(dir, n);
          const Vec3 X = C + lambda * dir - scene->plane_point;
          acc += texture(Dot(X, axis_u), Dot(X, axis_v));
        }
        img[static_cast<size_t>(v) * cam.width + u] = 0.25f * acc + (noise_sigma > 0.f ? noise(rng) : 0.f);
      }
    }
    scene->images.push_back(std::move(img));
  }
}

// True depth of pixel (u, v) of cam.
inline float PlaneSceneDepth(const PlaneScene& scene, const Camera& cam, int u, int v) {
  const Vec3 n_cam = MatVec(cam.R, scene.plane_normal);
  const Vec3 p_cam = MatVec(cam.R, scene.plane_point) + Vec3{cam.t[0], cam.t[1], cam.t[2]};
  return Dot(p_cam, n_cam) / Dot(PixelRay(cam, static_cast<float>(u), static_cast<float>(v)), n_cam);
}

// Camera 0 is the reference, every other camera a source.
inline PatchMatchProblem MakePlaneSceneProblem(const PlaneScene& scene, float depth_min, float depth_max) {
  PatchMatchProblem problem;
  problem.ref_camera = scene.cameras[0];
  problem.ref_image = ImageView{scene.images[0].data(), scene.cameras[0].width, scene.cameras[0].height};
  for (size_t s = 1; s < scene.cameras.size(); ++s) {
    PatchMatchSource src;
    src.camera = scene.cameras[s];
    src.image = ImageView{scene.images[s].data(), scene.cameras[s].width, scene.cameras[s].height};
    problem.sources.push_back(src);
  }
  problem.depth_min = depth_min;
  problem.depth_max = depth_max;
  return problem;
}

}  // namespace test
}  // namespace kernels
}  // namespace mpmvs
