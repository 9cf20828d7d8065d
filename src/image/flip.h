// LDR-FLIP: the perceptual difference evaluator of
//   P. Andersson, J. Nilsson, T. Akenine-Möller, M. Oskarsson, K. Åström, M. D. Fairchild,
//   "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact.
//   Tech. 3(2), 2020 (HPG 2020).
// Written from the paper; NVIDIA's reference implementation (github.com/NVlabs/flip) was read to
// settle constants and conventions the paper leaves implicit (filter radii, kernel normalisation,
// the reference illuminant). See flip.cpp for the pipeline, equation by equation.
//
// What FLIP measures: the difference a viewer perceives when flipping back and forth between two
// images shown at the same place on a display, at a given angular resolution (pixels per degree).
// The per-pixel value lies in [0,1]; 0 = no perceived difference.
//
// Conventions (shared with image/metrics.h):
//  - Inputs are LDR images, already tone mapped and sRGB encoded, channel values in [0,1] (the
//    output of rl::tonemap() with srgb on). Values are not clamped on input.
//  - The images must have the same non-zero size (and pixel count width x height), else
//    std::invalid_argument; a NaN or infinite channel is std::invalid_argument too, naming the
//    image ("test"/"reference") and the first such pixel.
//  - LDR-FLIP is symmetric: swapping test and reference gives the same map (every per-pixel term
//    of the paper is a symmetric function of the two filtered images). The order of the arguments
//    only matters for the messages of the errors.
#pragma once
#include "image/image.h"

namespace rl {

// Per-pixel FLIP error in [0,1], stored in all three channels of the returned image.
Image flip_error_map(const Image& test_srgb, const Image& reference_srgb, float pixels_per_degree = 67.0f);

// Mean of the FLIP error map over all pixels (accumulated in double).
double mean_flip(const Image& test_srgb, const Image& reference_srgb, float pixels_per_degree = 67.0f);

// Angular resolution of the display as seen by the observer (the paper's viewing conditions):
//   ppd = d * (W_px / W_m) * pi / 180
// for viewing distance d and display width W_m (metres) spanning W_px pixels. The defaults (0.7 m
// from a 0.7 m wide 4K monitor) give the paper's 67.02 pixels per degree. Arguments that are not
// positive and finite throw std::invalid_argument.
float flip_pixels_per_degree(float distance_m = 0.7f, float display_width_m = 0.7f, int display_width_px = 3840);

}  // namespace rl
