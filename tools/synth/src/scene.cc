// Ray casting against the boxes of the scene (slab method), and the preset room.
#include <omnidso/synth/scene.hpp>

#include <cmath>
#include <limits>

#include <omnidso/core/error.hpp>
#include <omnidso/synth/random.hpp>

namespace omnidso::synth {

Scene::Scene(std::vector<SceneBox> boxes, std::vector<Texture> textures, AlignedBox free_space)
    : boxes_(std::move(boxes)), textures_(std::move(textures)), free_space_(free_space) {
  for (const SceneBox& box : boxes_) {
    cos_yaw_.push_back(std::cos(box.yaw));
    sin_yaw_.push_back(std::sin(box.yaw));
    bounding_radius_sq_.push_back(box.half_size.squaredNorm());
  }
}

AlignedBox Scene::roomBounds() const {
  const SceneBox& room = boxes_.front();
  return {(room.centre - room.half_size).cast<double>(),
          (room.centre + room.half_size).cast<double>()};
}

Scene::PreparedOrigin Scene::prepare(const Eigen::Vector3f& origin) const {
  PreparedOrigin prepared;
  for (size_t b = 0; b < boxes_.size(); ++b) {
    const Eigen::Vector3f rel = origin - boxes_[b].centre;
    const float c = cos_yaw_[b];
    const float s = sin_yaw_[b];
    prepared.in_box.emplace_back(c * rel.x() + s * rel.y(), -s * rel.x() + c * rel.y(),
                                 rel.z());
    prepared.to_centre.push_back(-rel);
    prepared.centre_distance_sq.push_back(rel.squaredNorm());
  }
  return prepared;
}

bool Scene::intersect(const PreparedOrigin& origin, const Eigen::Vector3f& direction,
                      RayHit* hit) const {
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  const Eigen::Vector3f inv_world = direction.cwiseInverse();
  float best = kInfinity;
  int best_box = -1;
  int best_axis = 0;
  for (size_t b = 0; b < boxes_.size(); ++b) {
    const SceneBox& box = boxes_[b];
    if (!box.inside_out) {
      // Bounding-sphere rejection (most rays miss most boxes): the ray passes the centre at
      // along-ray distance a = d·(c − o) with squared miss distance |c − o|² − a².
      const float along = direction.dot(origin.to_centre[b]);
      const float miss_sq = origin.centre_distance_sq[b] - along * along;
      if (miss_sq > bounding_radius_sq_[b]) continue;
      const float radius = std::sqrt(bounding_radius_sq_[b]);
      if (along + radius < 0.f || along - radius >= best) continue;
    }
    const Eigen::Vector3f& o = origin.in_box[b];
    // The direction in the box frame (rotation by −yaw about z); axis-aligned boxes share
    // the world direction's reciprocal.
    Eigen::Vector3f inv = inv_world;
    if (box.yaw != 0.f) {
      const float c = cos_yaw_[b];
      const float s = sin_yaw_[b];
      inv.x() = 1.f / (c * direction.x() + s * direction.y());
      inv.y() = 1.f / (-s * direction.x() + c * direction.y());
    }
    // Slab method: along axis a the ray is inside the slab |p_a| ≤ h_a for λ between
    // (−h_a − o_a)/d_a and (h_a − o_a)/d_a (IEEE infinities handle d_a = 0).
    float t_near = -kInfinity;
    float t_far = kInfinity;
    int near_axis = 0;
    int far_axis = 0;
    for (int a = 0; a < 3; ++a) {
      float t0 = (-box.half_size[a] - o[a]) * inv[a];
      float t1 = (box.half_size[a] - o[a]) * inv[a];
      if (t0 > t1) std::swap(t0, t1);
      if (t0 > t_near) {
        t_near = t0;
        near_axis = a;
      }
      if (t1 < t_far) {
        t_far = t1;
        far_axis = a;
      }
    }
    // From inside the room a ray leaves through its nearest far plane; a solid box is hit
    // at its entry, if the slabs overlap.
    const float distance = box.inside_out ? t_far : t_near;
    if (!box.inside_out && t_near > t_far) continue;
    if (!(distance > 1e-6f) || distance >= best) continue;
    best = distance;
    best_box = static_cast<int>(b);
    best_axis = box.inside_out ? far_axis : near_axis;
  }
  if (best_box < 0) return false;
  // Texture coordinates of the nearest hit only.
  const SceneBox& box = boxes_[static_cast<size_t>(best_box)];
  const float c = cos_yaw_[static_cast<size_t>(best_box)];
  const float s = sin_yaw_[static_cast<size_t>(best_box)];
  const Eigen::Vector3f d(c * direction.x() + s * direction.y(),
                          -s * direction.x() + c * direction.y(), direction.z());
  const Eigen::Vector3f p = origin.in_box[static_cast<size_t>(best_box)] + best * d;
  const bool positive_side = box.inside_out ? d[best_axis] > 0 : d[best_axis] < 0;
  const int a1 = (best_axis + 1) % 3;
  const int a2 = (best_axis + 2) % 3;
  hit->distance = best;
  hit->box = best_box;
  hit->face = 2 * best_axis + (positive_side ? 1 : 0);
  hit->s = p[a1] + box.half_size[a1];
  hit->t = p[a2] + box.half_size[a2];
  return true;
}

float Scene::radianceAlong(const Eigen::Vector3f& origin,
                           const Eigen::Vector3f& direction) const {
  RayHit hit;
  return intersect(origin, direction, &hit) ? radiance(hit) : 0.f;
}

namespace {

struct ObjectSpec {
  Eigen::Vector3d centre;  // in the 8 × 6 × 3 m reference room
  Eigen::Vector3d half_size;
  double yaw;
};

// Furniture of the reference room: along the walls, none inside the free space.
const std::array<ObjectSpec, 10>& referenceObjects() {
  static const std::array<ObjectSpec, 10> kObjects = {{
      {{2.0, 0.3, 1.0}, {0.9, 0.3, 1.0}, 0.0},     // shelf against the y = 0 wall
      {{7.0, 3.0, 0.4}, {0.5, 0.9, 0.4}, 0.0},     // table
      {{1.0, 4.6, 0.6}, {0.4, 0.6, 0.6}, 0.3},     // cabinet, turned
      {{4.0, 5.3, 0.3}, {0.35, 0.35, 0.3}, 0.6},   // crate, turned
      {{6.4, 0.8, 0.9}, {0.3, 0.3, 0.9}, 0.0},     // tall cupboard
      {{4.0, 1.0, 2.6}, {0.4, 0.4, 0.25}, 0.4},    // box hanging under the ceiling
      {{0.6, 1.6, 1.5}, {0.2, 0.2, 1.5}, 0.0},     // pillar
      {{7.0, 2.6, 0.95}, {0.15, 0.2, 0.15}, 0.5},  // small box on the table
      {{5.8, 5.0, 0.45}, {0.3, 0.3, 0.45}, -0.4},  // chair-sized box
      {{2.0, 3.0, 0.2}, {0.4, 0.5, 0.2}, 0.0},     // low box under the free space
  }};
  return kObjects;
}

TextureRecipe wallRecipe(int face, SeededRandom& random) {
  TextureRecipe recipe;
  recipe.mean = static_cast<float>(random.uniform(0.35, 0.6));
  recipe.contrast = static_cast<float>(random.uniform(0.2, 0.35));
  recipe.octaves = 7;
  recipe.posters_per_m2 = 1.0;
  recipe.lines_per_m2 = 0.8;
  if (face == 4) {  // floor: more lines and fewer posters (rugs)
    recipe.posters_per_m2 = 0.3;
    recipe.lines_per_m2 = 1.2;
  } else if (face == 5) {  // ceiling: low contrast, lamps
    recipe.contrast = 0.06f;
    recipe.posters_per_m2 = 0.05;
    recipe.bright_patches_per_m2 = 0.12;
  } else if (face == 1) {  // one wall with nearly textureless stretches (paper's T5)
    recipe.flat_patches_per_m2 = 0.25;
  }
  return recipe;
}

}  // namespace

Scene makeRoomScene(const RoomSceneConfig& config, std::uint64_t seed) {
  const Eigen::Vector3d scale = config.room_size.cwiseQuotient(Eigen::Vector3d(8.0, 6.0, 3.0));
  AlignedBox free_space{Eigen::Vector3d(2.5, 2.0, 0.9).cwiseProduct(scale),
                        Eigen::Vector3d(5.5, 4.0, 2.0).cwiseProduct(scale)};
  SeededRandom random(counterHash(seed, 0x5CE7E));
  std::vector<SceneBox> boxes;
  std::vector<Texture> textures;
  auto addTextures = [&](SceneBox& box, bool is_room) {
    for (int face = 0; face < 6; ++face) {
      const int axis = face / 2;
      const double w = 2.0 * box.half_size[(axis + 1) % 3];
      const double h = 2.0 * box.half_size[(axis + 2) % 3];
      TextureRecipe recipe;
      if (is_room) {
        recipe = wallRecipe(face, random);
      } else {
        recipe.mean = static_cast<float>(random.uniform(0.15, 0.8));
        recipe.contrast = static_cast<float>(random.uniform(0.05, 0.3));
        recipe.largest_wavelength_m = random.uniform(0.2, 0.8);
        recipe.posters_per_m2 = random.uniform(0.0, 2.0);
        recipe.lines_per_m2 = random.uniform(0.0, 2.0);
      }
      box.face_texture[face] = static_cast<int>(textures.size());
      textures.emplace_back(makeProceduralRadiance(w, h, config.texel_size, recipe, random.bits()),
                            config.texel_size);
    }
  };

  SceneBox room;
  room.centre = (0.5 * config.room_size).cast<float>();
  room.half_size = (0.5 * config.room_size).cast<float>();
  room.inside_out = true;
  addTextures(room, true);
  boxes.push_back(room);
  for (const ObjectSpec& object : referenceObjects()) {
    SceneBox box;
    box.centre = object.centre.cwiseProduct(scale).cast<float>();
    box.half_size = object.half_size.cwiseProduct(scale).cast<float>();
    box.yaw = static_cast<float>(object.yaw);
    addTextures(box, false);
    boxes.push_back(box);
  }
  if (!config.poster_images.empty()) {
    // Posters from image files on the four walls in turn, 1.2 m wide, 0.9 m high, 1 m up.
    for (size_t i = 0; i < config.poster_images.size(); ++i) {
      const int face = static_cast<int>(i % 4);
      const int texture_index = boxes.front().face_texture[face];
      const Texture& old = textures[static_cast<size_t>(texture_index)];
      ImageF radiance(old.paddedRadiance().width() - 1, old.paddedRadiance().height() - 1);
      for (int v = 0; v < radiance.height(); ++v) {
        for (int u = 0; u < radiance.width(); ++u) radiance(u, v) = old.paddedRadiance()(u, v);
      }
      // Face axes: x faces run (y, z), y faces run (z, x); place 1 m along, 1 m up.
      const bool x_face = face < 2;
      const double s = x_face ? 1.0 + 1.5 * static_cast<double>(i / 4) : 1.0;
      const double t = x_face ? 1.0 : 1.0 + 1.5 * static_cast<double>(i / 4);
      pasteImagePoster(radiance, config.texel_size, config.poster_images[i], s, t,
                       x_face ? 1.2 : 0.9, x_face ? 0.9 : 1.2);
      textures[static_cast<size_t>(texture_index)] = Texture(radiance, config.texel_size);
    }
  }
  return Scene(std::move(boxes), std::move(textures), free_space);
}

}  // namespace omnidso::synth
