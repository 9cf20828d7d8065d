// What the binding files of the `restirlab` module share: numpy <-> Image, option dictionaries.
// Bindings only: every computation is a call into src/.
#pragma once
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "image/image.h"

namespace rl::py {

namespace nb = nanobind;

// An H x W x 3 float32 array, the layout of Image::pixels (row-major rows of packed Rgb).
using ImageArray = nb::ndarray<nb::numpy, float, nb::shape<-1, -1, 3>, nb::c_contig, nb::device::cpu>;
using ImageInput = nb::ndarray<const float, nb::shape<-1, -1, 3>, nb::c_contig, nb::device::cpu>;
static_assert(sizeof(Rgb) == 3 * sizeof(float), "Image::pixels must be packed float triples for numpy views");

// A view of img's pixels (no copy) that keeps `owner` alive while the array lives.
ImageArray image_view(Image& img, nb::handle owner);
// The image moved into an array that owns it (no copy of the pixels).
ImageArray image_array(Image&& img);
// A copy of an array as an Image.
Image to_image(const ImageInput& a);

// A dict of options, nested ({"pt": {"shift": "hybrid"}}) or dotted ({"pt.shift": "hybrid"}), as
// (dotted key, value text) pairs in the dict's order: the text `--set key=value` would carry
// (bools as true/false, floats as Python's shortest round-trip repr).
std::vector<std::pair<std::string, std::string>> option_assignments(nb::handle options);
// The optional dict of a binding's signature (typed `dict | None` in the stubs) as a handle.
inline nb::handle dict_or_none(const std::optional<nb::dict>& d) { return d ? nb::handle(*d) : nb::handle(Py_None); }

void bind_renderer(nb::module_& m);
void bind_images(nb::module_& m);

}  // namespace rl::py
