#pragma once
// The synthetic 3D scene: a room (an inside-out box: floor, ceiling, four walls) and
// furniture-sized boxes (axis-aligned or turned about the vertical axis), every face
// textured (texture.hpp). Rays are intersected analytically (slab method per box) and the
// nearest hit wins, so any central camera model renders over its whole field of view.
//
// World frame: z up, the room spans [0, size.x] × [0, size.y] × [0, size.z] metres. A
// "free space" box inside the room holds no object: camera paths are confined to it.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <omnidso/synth/texture.hpp>

namespace omnidso::synth {

struct AlignedBox {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  Eigen::Vector3d centre() const { return 0.5 * (min + max); }
  Eigen::Vector3d size() const { return max - min; }
  bool contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

// A box of the scene. Faces are numbered 2·axis + (0 for the −axis side, 1 for +axis);
// face f is textured by textures[face_texture[f]].
struct SceneBox {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f half_size = Eigen::Vector3f::Ones();
  float yaw = 0.f;            // rotation about the world z axis (box frame → world)
  bool inside_out = false;    // the room: rays start inside and hit its faces from within
  std::array<int, 6> face_texture{};
};

struct RayHit {
  float distance = 0.f;  // along the unit ray direction
  int box = -1;
  int face = -1;
  float s = 0.f;  // texture coordinates on the face, metres
  float t = 0.f;
};

class Scene {
 public:
  Scene(std::vector<SceneBox> boxes, std::vector<Texture> textures, AlignedBox free_space);

  // A ray origin expressed once in every box's frame: all rays of a frame share it, so the
  // renderer prepares it once per pose.
  struct PreparedOrigin {
    std::vector<Eigen::Vector3f> in_box;         // the origin in each box's frame
    std::vector<Eigen::Vector3f> to_centre;      // box centre − origin (world)
    std::vector<float> centre_distance_sq;       // its squared norm
  };
  PreparedOrigin prepare(const Eigen::Vector3f& origin) const;

  // Nearest hit of the ray origin + λ·direction, λ > 0 (direction of unit length);
  // false when nothing is hit (cannot happen from inside the room).
  bool intersect(const PreparedOrigin& origin, const Eigen::Vector3f& direction,
                 RayHit* hit) const;
  bool intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction,
                 RayHit* hit) const {
    return intersect(prepare(origin), direction, hit);
  }
  float radiance(const RayHit& hit) const {
    return textures_[static_cast<size_t>(
                         boxes_[static_cast<size_t>(hit.box)].face_texture[hit.face])]
        .sample(hit.s, hit.t);
  }
  // Radiance seen along a ray (0 if nothing is hit).
  float radianceAlong(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction) const;

  const std::vector<SceneBox>& boxes() const { return boxes_; }
  const std::vector<Texture>& textures() const { return textures_; }
  const AlignedBox& freeSpace() const { return free_space_; }
  // The room's box (boxes()[0]).
  AlignedBox roomBounds() const;

 private:
  std::vector<SceneBox> boxes_;  // boxes_[0] is the room
  std::vector<float> cos_yaw_, sin_yaw_;
  std::vector<float> bounding_radius_sq_;  // of the sphere around each box
  std::vector<Texture> textures_;
  AlignedBox free_space_;
};

struct RoomSceneConfig {
  Eigen::Vector3d room_size{8.0, 6.0, 3.0};  // metres (x, y, z)
  double texel_size = 0.01;                  // metres per texel (≈ a pixel at 1.5 m)
  // Image files pasted as posters on the walls (optional; grey levels → radiance).
  std::vector<std::string> poster_images;
};

// The indoor room of the presets: furniture along the walls at depths 0.5–4 m from the
// free space in the middle, textures with posters, lines, lamps and a textureless stretch
// of wall. The layout is fixed (scaled with room_size); the seed chooses the textures.
Scene makeRoomScene(const RoomSceneConfig& config, std::uint64_t seed);

}  // namespace omnidso::synth
