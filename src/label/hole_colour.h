#pragma once
// An optional colour test on depth holes (VisibilityOptions::hole_colour, docs/labels.md "Depth holes
// and colour"): a pixel without depth that the hole rule leaves visible is hidden when its colour is one
// the object never shows. It catches what depth cannot: a hand nearer than the sensor's minimum range
// over an object looks, in depth, exactly like a dark patch on the object or like the object itself
// nearer than the range (all are holes the object's surface or nothing encloses); in colour, the patch
// and the object are the object's colours and the hand is not.
//
// What the object's colours are comes from two references, either of which may be missing: its own
// visible pixels with depth in this frame (what the camera shows of it, with the lighting and the
// camera's colour response), and its mesh's vertex colours and texture (what it is made of, known even
// when the whole object is nearer than the sensor's range and has no depth). A colour is foreign when
// every reference there is lacks it. Colour is compared by chromaticity (R and G over R + G + B), which
// shading by white light leaves alone; pixels too dark to carry a chromaticity are never foreign.
#include <cstddef>
#include <cstdint>
#include <map>
#include <vector>

#include "core/image.h"
#include "label/visibility.h"
#include "render/canvas.h"
#include "render/mesh.h"

namespace mocap {

/// An 8-bit BGR image (OpenCV's CV_8UC3 layout) the labels' camera took; not owned.
struct BgrView {
  int width = 0, height = 0;
  const uint8_t* data = nullptr;
  size_t step = 0;  ///< bytes per row
  const uint8_t* at(int u, int v) const { return data + static_cast<size_t>(v) * step + 3 * static_cast<size_t>(u); }
};

/// A weighted chromaticity histogram (hole_colour_bins per axis).
class ColourHistogram {
 public:
  explicit ColourHistogram(const VisibilityOptions& options);
  /// Adds a colour (8-bit levels) with a weight; ignored when too dark to carry a chromaticity.
  void Add(int red, int green, int blue, double weight = 1.0);
  /// The bin of a colour, or -1 when it is too dark.
  int Bin(int red, int green, int blue) const;
  /// The histogram's share of `bin` and the 8 bins around it (noise and small hue shifts move a colour
  /// by a bin); 0 when empty.
  double ShareAround(int bin) const;
  double total() const { return total_; }

 private:
  int bins_, min_level_;
  std::vector<double> weights_;
  double total_ = 0;
};

/// The colours of a mesh: its vertex colours weighted by the area of the triangles around them, and
/// its texture's texels. Empty (total 0) when the mesh has neither.
ColourHistogram MeshColours(const Mesh& mesh, const VisibilityOptions& options);

/// What the colour test on holes needs of a frame.
struct HoleColours {
  BgrView image;
  /// Per instance id, its mesh's colours (MeshColours); an instance not listed has no mesh reference.
  std::map<uint16_t, const ColourHistogram*> mesh_colours;
};

/// Clears from `visible` (a mask over `rect` of instance `instance_id`) the pixels without measured
/// depth whose colour is foreign to the object (above). Returns how many it cleared. Preconditions:
/// `measured_m` and the colour image have the camera's size and contain `rect`.
int HideForeignHoles(uint16_t instance_id, const PixelRect& rect, const DepthImage& measured_m,
                     const HoleColours& colours, const VisibilityOptions& options, std::vector<uint8_t>& visible);

}  // namespace mocap
