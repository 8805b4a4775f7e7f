#pragma once
// Ray casting geometry of synthetic scenes: quads (optionally with rectangular holes, for
// walls with window openings), oriented boxes, spheres and capped cylinders, in a small
// bounding-volume hierarchy. Ray directions need not be unit length: t is measured in
// units of the direction, so a camera ray with camera-frame z = 1 hits at t = z-depth.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mpmvs {

struct SceneRay {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

struct SceneHit {
  double t = 0;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // world frame, unit, not oriented
  int primitive = -1;
  int material = -1;
};

enum class PrimitiveType { kQuad, kBox, kSphere, kCylinder };

// Rectangle [u0,u1] x [v0,v1] in a quad's local coordinates (metres from its centre).
struct QuadHole {
  double u0 = 0, v0 = 0, u1 = 0, v1 = 0;
};

struct ScenePrimitive {
  PrimitiveType type = PrimitiveType::kQuad;
  int material = 0;
  bool casts_shadow = true;  // false for room shells that must not block interior lights
  // Quad/box/sphere: centre. Cylinder: centre of the base disk.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  // Columns are the local x, y, z axes (orthonormal). Quad: u, v, normal. Cylinder: z = axis.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  // Quad: (half u, half v, 0). Box: half extents. Cylinder: (radius, radius, height).
  Eigen::Vector3d half_size = Eigen::Vector3d::Zero();
  double radius = 0;  // sphere, cylinder
  std::vector<QuadHole> holes;  // quad only
};

ScenePrimitive MakeQuad(const Eigen::Vector3d& center, const Eigen::Vector3d& u_axis,
                        const Eigen::Vector3d& v_axis, double half_u, double half_v,
                        int material);
// Axis-aligned box from its min and max corner.
ScenePrimitive MakeBox(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
                       int material);
// Box rotated by yaw (radians) about the world z axis.
ScenePrimitive MakeYawedBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half_size,
                            double yaw, int material);
ScenePrimitive MakeSphere(const Eigen::Vector3d& center, double radius, int material);
ScenePrimitive MakeCylinder(const Eigen::Vector3d& base_center, const Eigen::Vector3d& axis,
                            double radius, double height, int material);

// Nearest hit of one primitive with t in (t_min, t_max).
bool IntersectPrimitive(const ScenePrimitive& primitive, const SceneRay& ray, double t_min,
                        double t_max, SceneHit* hit);
Eigen::AlignedBox3d PrimitiveBounds(const ScenePrimitive& primitive);

class SceneGeometry {
 public:
  int Add(const ScenePrimitive& primitive);
  // Must be called after the last Add and before any query.
  void Build();

  bool Intersect(const SceneRay& ray, double t_min, double t_max, SceneHit* hit) const;
  // Any shadow-casting primitive between t_min and t_max.
  bool Occluded(const SceneRay& ray, double t_min, double t_max) const;

  const std::vector<ScenePrimitive>& primitives() const { return primitives_; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children, or -1 for a leaf
    int first = 0, count = 0;   // leaf range in order_
  };
  int BuildNode(int first, int count, const std::vector<Eigen::Vector3d>& centroids);
  template <bool kAnyHit>
  bool Traverse(const SceneRay& ray, double t_min, double t_max, SceneHit* hit) const;

  std::vector<ScenePrimitive> primitives_;
  std::vector<Eigen::AlignedBox3d> bounds_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

}  // namespace mpmvs
