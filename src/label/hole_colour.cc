#include "label/hole_colour.h"

#include <Eigen/Geometry>
#include <algorithm>

namespace mocap {

ColourHistogram::ColourHistogram(const VisibilityOptions& options)
    : bins_(options.hole_colour_bins),
      min_level_(options.hole_colour_min_level),
      weights_(static_cast<size_t>(bins_ * bins_), 0.0) {}

int ColourHistogram::Bin(int red, int green, int blue) const {
  const int sum = red + green + blue;
  if (sum < 3 * min_level_ || sum == 0) return -1;
  const int r = std::min(bins_ - 1, red * bins_ / sum), g = std::min(bins_ - 1, green * bins_ / sum);
  return r * bins_ + g;
}

void ColourHistogram::Add(int red, int green, int blue, double weight) {
  const int bin = Bin(red, green, blue);
  if (bin < 0 || !(weight > 0)) return;
  weights_[static_cast<size_t>(bin)] += weight, total_ += weight;
}

double ColourHistogram::ShareAround(int bin) const {
  if (!(total_ > 0)) return 0;
  const int r = bin / bins_, g = bin % bins_;
  double near = 0;
  for (int i = std::max(0, r - 1); i <= std::min(bins_ - 1, r + 1); ++i)
    for (int j = std::max(0, g - 1); j <= std::min(bins_ - 1, g + 1); ++j) near += weights_[static_cast<size_t>(i * bins_ + j)];
  return near / total_;
}

ColourHistogram MeshColours(const Mesh& mesh, const VisibilityOptions& options) {
  ColourHistogram h(options);
  const auto level = [](float x) { return static_cast<int>(std::clamp(x, 0.0f, 1.0f) * 255.0f + 0.5f); };
  if (mesh.colors.size() == mesh.positions_m.size()) {
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      const Eigen::Vector3f& a = mesh.positions_m[mesh.indices[t]];
      const double area =
          0.5 * (mesh.positions_m[mesh.indices[t + 1]] - a).cross(mesh.positions_m[mesh.indices[t + 2]] - a).norm();
      for (size_t k = 0; k < 3; ++k) {
        const Eigen::Vector4f& c = mesh.colors[mesh.indices[t + k]];
        h.Add(level(c[0]), level(c[1]), level(c[2]), area / 3.0);
      }
    }
  }
  for (size_t i = 0; i + 2 < mesh.texture.rgb.size(); i += 3)
    h.Add(mesh.texture.rgb[i], mesh.texture.rgb[i + 1], mesh.texture.rgb[i + 2]);
  return h;
}

namespace {

/// The object's references; a colour is foreign when every reference there is lacks it.
struct ObjectReferences {
  const ColourHistogram& observed;
  bool observed_known;
  const ColourHistogram* mesh;  ///< null when the mesh has no colours
  double max_share;

  bool known() const { return observed_known || mesh; }
  bool Foreign(const uint8_t* bgr) const {
    const int bin = observed.Bin(bgr[2], bgr[1], bgr[0]);
    if (bin < 0) return false;  // too dark to tell
    if (observed_known && observed.ShareAround(bin) >= max_share) return false;
    return !mesh || mesh->ShareAround(bin) < max_share;
  }
};

}  // namespace

int HideForeignHoles(uint16_t instance_id, const PixelRect& rect, const DepthImage& measured_m,
                     const HoleColours& colours, const VisibilityOptions& options, std::vector<uint8_t>& visible) {
  ColourHistogram observed(options);
  for (int v = 0; v < rect.height; ++v)
    for (int u = 0; u < rect.width; ++u)
      if (visible[static_cast<size_t>(v) * rect.width + u] && measured_m.at(rect.x + u, rect.y + v) > 0.0f) {
        const uint8_t* bgr = colours.image.at(rect.x + u, rect.y + v);
        observed.Add(bgr[2], bgr[1], bgr[0]);
      }
  const auto mesh = colours.mesh_colours.find(instance_id);
  const ColourHistogram* mesh_reference =
      mesh != colours.mesh_colours.end() && mesh->second && mesh->second->total() > 0 ? mesh->second : nullptr;
  const ObjectReferences references{observed, observed.total() >= options.hole_colour_min_reference_px, mesh_reference,
                                    options.hole_colour_max_share};
  if (!references.known()) return 0;
  int hidden = 0;
  for (int v = 0; v < rect.height; ++v)
    for (int u = 0; u < rect.width; ++u) {
      uint8_t& in = visible[static_cast<size_t>(v) * rect.width + u];
      if (!in || measured_m.at(rect.x + u, rect.y + v) > 0.0f || !references.Foreign(colours.image.at(rect.x + u, rect.y + v)))
        continue;
      in = 0, ++hidden;
    }
  return hidden;
}

}  // namespace mocap
