#include "colmap_ext/synthetic/scene_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mpmvs {
namespace {

constexpr double kParallelEps = 1e-12;

Eigen::Matrix3d FrameFromAxis(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d z = axis.normalized();
  const Eigen::Vector3d helper =
      std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = helper.cross(z).normalized();
  Eigen::Matrix3d axes;
  axes.col(0) = x;
  axes.col(1) = z.cross(x);
  axes.col(2) = z;
  return axes;
}

bool HitQuad(const ScenePrimitive& q, const SceneRay& ray, double t_min, double t_max,
             SceneHit* hit) {
  const Eigen::Vector3d n = q.axes.col(2);
  const double denom = n.dot(ray.direction);
  if (std::abs(denom) < kParallelEps) return false;
  const double t = n.dot(q.center - ray.origin) / denom;
  if (!(t > t_min && t < t_max)) return false;
  const Eigen::Vector3d p = ray.origin + t * ray.direction - q.center;
  const double u = p.dot(q.axes.col(0)), v = p.dot(q.axes.col(1));
  if (std::abs(u) > q.half_size.x() || std::abs(v) > q.half_size.y()) return false;
  for (const QuadHole& h : q.holes) {
    if (u > h.u0 && u < h.u1 && v > h.v0 && v < h.v1) return false;
  }
  hit->t = t;
  hit->normal = n;
  return true;
}

bool HitBox(const ScenePrimitive& b, const SceneRay& ray, double t_min, double t_max,
            SceneHit* hit) {
  const Eigen::Vector3d o = b.axes.transpose() * (ray.origin - b.center);
  const Eigen::Vector3d d = b.axes.transpose() * ray.direction;
  double t_near = -std::numeric_limits<double>::infinity();
  double t_far = std::numeric_limits<double>::infinity();
  int near_axis = -1, far_axis = -1;
  double near_sign = 0, far_sign = 0;
  for (int i = 0; i < 3; ++i) {
    const double h = b.half_size[i];
    if (std::abs(d[i]) < kParallelEps) {
      if (o[i] < -h || o[i] > h) return false;
      continue;
    }
    double t0 = (-h - o[i]) / d[i], t1 = (h - o[i]) / d[i];
    double s0 = -1, s1 = 1;  // outward normal sign of the face hit at t0 / t1
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(s0, s1);
    }
    if (t0 > t_near) {
      t_near = t0;
      near_axis = i;
      near_sign = s0;
    }
    if (t1 < t_far) {
      t_far = t1;
      far_axis = i;
      far_sign = s1;
    }
    if (t_near > t_far) return false;
  }
  double t;
  int axis;
  double sign;
  if (t_near > t_min && t_near < t_max && near_axis >= 0) {
    t = t_near, axis = near_axis, sign = near_sign;
  } else if (t_far > t_min && t_far < t_max && far_axis >= 0) {
    t = t_far, axis = far_axis, sign = far_sign;
  } else {
    return false;
  }
  hit->t = t;
  hit->normal = sign * b.axes.col(axis);
  return true;
}

bool HitSphere(const ScenePrimitive& s, const SceneRay& ray, double t_min, double t_max,
               SceneHit* hit) {
  const Eigen::Vector3d oc = ray.origin - s.center;
  const double a = ray.direction.squaredNorm();
  const double half_b = oc.dot(ray.direction);
  const double c = oc.squaredNorm() - s.radius * s.radius;
  const double disc = half_b * half_b - a * c;
  if (disc < 0) return false;
  const double root = std::sqrt(disc);
  double t = (-half_b - root) / a;
  if (!(t > t_min && t < t_max)) {
    t = (-half_b + root) / a;
    if (!(t > t_min && t < t_max)) return false;
  }
  hit->t = t;
  hit->normal = (ray.origin + t * ray.direction - s.center) / s.radius;
  return true;
}

bool HitCylinder(const ScenePrimitive& c, const SceneRay& ray, double t_min, double t_max,
                 SceneHit* hit) {
  const Eigen::Vector3d o = c.axes.transpose() * (ray.origin - c.center);
  const Eigen::Vector3d d = c.axes.transpose() * ray.direction;
  const double r = c.radius, h = c.half_size.z();
  double best = t_max;
  Eigen::Vector3d best_normal_local;
  bool found = false;
  // Side wall.
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a > kParallelEps) {
    const double half_b = o.x() * d.x() + o.y() * d.y();
    const double cc = o.x() * o.x() + o.y() * o.y() - r * r;
    const double disc = half_b * half_b - a * cc;
    if (disc >= 0) {
      const double root = std::sqrt(disc);
      for (double t : {(-half_b - root) / a, (-half_b + root) / a}) {
        if (t > t_min && t < best) {
          const double z = o.z() + t * d.z();
          if (z >= 0 && z <= h) {
            best = t;
            best_normal_local = Eigen::Vector3d(o.x() + t * d.x(), o.y() + t * d.y(), 0) / r;
            found = true;
            break;
          }
        }
      }
    }
  }
  // End caps.
  if (std::abs(d.z()) > kParallelEps) {
    for (double zc : {0.0, h}) {
      const double t = (zc - o.z()) / d.z();
      if (t > t_min && t < best) {
        const double x = o.x() + t * d.x(), y = o.y() + t * d.y();
        if (x * x + y * y <= r * r) {
          best = t;
          best_normal_local = Eigen::Vector3d(0, 0, zc == 0 ? -1 : 1);
          found = true;
        }
      }
    }
  }
  if (!found) return false;
  hit->t = best;
  hit->normal = c.axes * best_normal_local;
  return true;
}

bool RayHitsBox(const Eigen::AlignedBox3d& box, const SceneRay& ray, double t_min,
                double t_max) {
  for (int i = 0; i < 3; ++i) {
    const double o = ray.origin[i], d = ray.direction[i];
    if (std::abs(d) < kParallelEps) {
      if (o < box.min()[i] || o > box.max()[i]) return false;
      continue;
    }
    double t0 = (box.min()[i] - o) / d, t1 = (box.max()[i] - o) / d;
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
    if (t_min > t_max) return false;
  }
  return true;
}

}  // namespace

ScenePrimitive MakeQuad(const Eigen::Vector3d& center, const Eigen::Vector3d& u_axis,
                        const Eigen::Vector3d& v_axis, double half_u, double half_v,
                        int material) {
  ScenePrimitive p;
  p.type = PrimitiveType::kQuad;
  p.material = material;
  p.center = center;
  const Eigen::Vector3d u = u_axis.normalized();
  // Re-orthogonalise v so that (u, v, n) is an orthonormal frame.
  const Eigen::Vector3d v = (v_axis - v_axis.dot(u) * u).normalized();
  p.axes.col(0) = u;
  p.axes.col(1) = v;
  p.axes.col(2) = u.cross(v);
  p.half_size = Eigen::Vector3d(half_u, half_v, 0);
  return p;
}

ScenePrimitive MakeBox(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner,
                       int material) {
  ScenePrimitive p;
  p.type = PrimitiveType::kBox;
  p.material = material;
  p.center = 0.5 * (min_corner + max_corner);
  p.half_size = 0.5 * (max_corner - min_corner).cwiseAbs();
  return p;
}

ScenePrimitive MakeYawedBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half_size,
                            double yaw, int material) {
  ScenePrimitive p;
  p.type = PrimitiveType::kBox;
  p.material = material;
  p.center = center;
  p.half_size = half_size;
  p.axes = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

ScenePrimitive MakeSphere(const Eigen::Vector3d& center, double radius, int material) {
  ScenePrimitive p;
  p.type = PrimitiveType::kSphere;
  p.material = material;
  p.center = center;
  p.radius = radius;
  return p;
}

ScenePrimitive MakeCylinder(const Eigen::Vector3d& base_center, const Eigen::Vector3d& axis,
                            double radius, double height, int material) {
  ScenePrimitive p;
  p.type = PrimitiveType::kCylinder;
  p.material = material;
  p.center = base_center;
  p.axes = FrameFromAxis(axis);
  p.radius = radius;
  p.half_size = Eigen::Vector3d(radius, radius, height);
  return p;
}

bool IntersectPrimitive(const ScenePrimitive& primitive, const SceneRay& ray, double t_min,
                        double t_max, SceneHit* hit) {
  switch (primitive.type) {
    case PrimitiveType::kQuad:
      return HitQuad(primitive, ray, t_min, t_max, hit);
    case PrimitiveType::kBox:
      return HitBox(primitive, ray, t_min, t_max, hit);
    case PrimitiveType::kSphere:
      return HitSphere(primitive, ray, t_min, t_max, hit);
    case PrimitiveType::kCylinder:
      return HitCylinder(primitive, ray, t_min, t_max, hit);
  }
  return false;
}

Eigen::AlignedBox3d PrimitiveBounds(const ScenePrimitive& p) {
  Eigen::Vector3d lo = p.center, hi = p.center;
  switch (p.type) {
    case PrimitiveType::kQuad: {
      const Eigen::Vector3d e = p.axes.col(0).cwiseAbs() * p.half_size.x() +
                                p.axes.col(1).cwiseAbs() * p.half_size.y();
      lo = p.center - e;
      hi = p.center + e;
      break;
    }
    case PrimitiveType::kBox: {
      const Eigen::Vector3d e = p.axes.cwiseAbs() * p.half_size;
      lo = p.center - e;
      hi = p.center + e;
      break;
    }
    case PrimitiveType::kSphere:
      lo = p.center - Eigen::Vector3d::Constant(p.radius);
      hi = p.center + Eigen::Vector3d::Constant(p.radius);
      break;
    case PrimitiveType::kCylinder: {
      const Eigen::Vector3d top = p.center + p.axes.col(2) * p.half_size.z();
      lo = p.center.cwiseMin(top) - Eigen::Vector3d::Constant(p.radius);
      hi = p.center.cwiseMax(top) + Eigen::Vector3d::Constant(p.radius);
      break;
    }
  }
  // Flat quads get a little thickness so the slab test never degenerates.
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(1e-6);
  return Eigen::AlignedBox3d(lo - pad, hi + pad);
}

int SceneGeometry::Add(const ScenePrimitive& primitive) {
  primitives_.push_back(primitive);
  return static_cast<int>(primitives_.size()) - 1;
}

void SceneGeometry::Build() {
  const int n = static_cast<int>(primitives_.size());
  bounds_.resize(n);
  std::vector<Eigen::Vector3d> centroids(n);
  order_.resize(n);
  for (int i = 0; i < n; ++i) {
    bounds_[i] = PrimitiveBounds(primitives_[i]);
    centroids[i] = bounds_[i].center();
    order_[i] = i;
  }
  nodes_.clear();
  if (n > 0) BuildNode(0, n, centroids);
}

int SceneGeometry::BuildNode(int first, int count, const std::vector<Eigen::Vector3d>& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box;
  Eigen::AlignedBox3d centroid_box;
  for (int i = first; i < first + count; ++i) {
    box.extend(bounds_[order_[i]]);
    centroid_box.extend(centroids[order_[i]]);
  }
  nodes_[index].box = box;
  if (count <= 2) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis = 0;
  centroid_box.sizes().maxCoeff(&axis);
  const int mid = first + count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                   [&](int a, int b) {
                     if (centroids[a][axis] != centroids[b][axis]) {
                       return centroids[a][axis] < centroids[b][axis];
                     }
                     return a < b;  // deterministic tie-break
                   });
  const int left = BuildNode(first, mid - first, centroids);
  const int right = BuildNode(mid, first + count - mid, centroids);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

template <bool kAnyHit>
bool SceneGeometry::Traverse(const SceneRay& ray, double t_min, double t_max,
                             SceneHit* hit) const {
  if (nodes_.empty()) return false;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  bool found = false;
  double best = t_max;
  SceneHit candidate;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!RayHitsBox(node.box, ray, t_min, best)) continue;
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int id = order_[i];
        const ScenePrimitive& p = primitives_[id];
        if (kAnyHit && !p.casts_shadow) continue;
        if (IntersectPrimitive(p, ray, t_min, best, &candidate)) {
          if (kAnyHit) return true;
          found = true;
          best = candidate.t;
          candidate.primitive = id;
          candidate.material = p.material;
          *hit = candidate;
        }
      }
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  return found;
}

bool SceneGeometry::Intersect(const SceneRay& ray, double t_min, double t_max,
                              SceneHit* hit) const {
  return Traverse<false>(ray, t_min, t_max, hit);
}

bool SceneGeometry::Occluded(const SceneRay& ray, double t_min, double t_max) const {
  return Traverse<true>(ray, t_min, t_max, nullptr);
}

}  // namespace mpmvs
