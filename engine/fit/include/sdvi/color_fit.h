// SPDX-License-Identifier: GPL-3.0-or-later
// Colour fit (paper eq. 2-3, spec/METHOD.md section 5): the control positions are fixed, the
// control colours are the unknowns of a linear least-squares problem
//
//   min over COLOR(V)  sum over domain pixels p  || I(p) - C_p COLOR(V) ||^2
//                      + lambda * s * sum over control edges (i,j) || c_i - c_j ||^2
//
// where C_p = (barycentrics of p's centre in its fine triangle) x (the limit stencils of that
// triangle's three fine vertices), i.e. exactly what the renderer draws at the same level.
// The pixel -> fine triangle map is MapPixels at the identity viewport: the one rendering
// uses, held as one owner per pixel (PixelOwners, sdvi/render.h), the weights computed
// again where they are read. Assembly goes through the fine level: per fine triangle the moments
// sum w_a w_b and sum w_a I(p) form a fine normal matrix F and right-hand side g, which
// are projected through the stencil matrix S (fine x control): A = S^T F S, b = S^T g
// (three right-hand sides R, G, B; one matrix). The solve is conjugate gradients
// preconditioned by an incomplete Cholesky factor (Eigen), to a relative residual of 1e-8,
// with a sparse LDL^T as the fallback when CG does not converge in 2000 iterations. CG starts
// from the target's colour at each control vertex's pixel, or, with warm_start, from the
// colours the vertices carry on entry (Vectorize passes the previous round's fit).
// The three channels' solves run on up to three threads (ColorFitOptions::threads), each
// exactly the single-threaded solve, so deterministic for a given input (and start).
//
// Regulariser: the second term is a graph-Laplacian (membrane / diffusion) energy over the
// control mesh's edges, weighted by lambda times s = the mean diagonal of the data matrix
// S^T F S, so that lambda is dimensionless. Vertices no pixel sees (outside an object's
// mask, or whose stencil weight falls on no pixel centre) get the harmonic interpolation
// of their neighbours' colours; with the default lambda = 1e-4 the data term dominates
// everywhere else (it moves well-determined colours by far less than one 8-bit level).
// A further 1e-9 * s on the diagonal keeps the system positive definite on components
// that no pixel reaches (their colours come out 0 rather than undefined).
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/raster.h"
#include "sdvi/render.h"
#include "sdvi/status.h"
#include "sdvi/subdiv.h"

namespace sdvi {

struct ColorFitOptions {
  // The surface whose colours are fitted: level r = 2 limit surface as in the paper.
  // levels = 0, to_limit = false fits piecewise-linear colours on the control mesh itself.
  LimitSurfaceOptions surface;
  double regularization = 1e-4;  // lambda of the header comment (relative, >= 0)
  bool warm_start = false;       // CG from the vertices' colours on entry (header comment)
  int threads = 1;               // assembly and solve threads (results do not depend on it)
};

// Everything the fit computed besides the colours, for reconstruction and error maps.
struct ColorFit {
  LimitSurface surface;         // the fine mesh fitted (stencils over the control vertices)
  std::vector<Vertex> fine;     // fine vertices with the fitted colours
  PixelOwners coverage;         // pixel -> fine triangle, identity viewport
  uint64_t domain_pixels = 0;   // pixels that entered the least squares
  double sum_squared_error = 0; // of the clamped reconstruction over the domain pixels and
                                // R, G, B (8-bit units^2)
  // Seconds spent per step.
  double seconds_surface = 0;   // BuildLimitSurface + EvaluateSurface
  double seconds_coverage = 0;  // MapPixelOwnersInto
  double seconds_assemble = 0;  // moments, projection through the stencils
  double seconds_solve = 0;     // factorisation and solve
};

// Storage that a caller fitting repeatedly (the vectorizer's rounds) hands from one
// FitColors call to the next: the per-pixel coverage array is written into memory already
// held instead of fresh pages that the kernel must zero first. Scratch: the contents do not
// matter, and the result is the same as without it.
struct ColorFitBuffers {
  std::vector<uint32_t> coverage;  // taken by the next fit; give back a fit's coverage.owner
};

// Fits the colours of image.vertices (positions unchanged; with options.warm_start their
// colours on entry are the solver's start, which moves the result within its tolerance) to
// target, a raster of the same size as image.width x image.height (grey, grey+alpha, RGB
// or RGBA; grey counts as R = G = B). The domain is the pixels covered by the fine mesh
// whose alpha (if any) is > 0.5 and, when a mask is given (same size), whose mask alpha is
// > 0.5 (mask with alpha) or whose mask channel 0 is > 127.5 (mask without alpha, 0..255).
// Errors: kInvalidArgument (size mismatch, bad options), the errors of BuildLimitSurface,
// kInternal when the factorisation fails. With buffers (non-null), the coverage storage is
// taken from them (see ColorFitBuffers).
StatusOr<ColorFit> FitColors(Image& image, const Raster& target, const Raster* mask,
                             const ColorFitOptions& options, ColorFitBuffers* buffers = nullptr);

// The RGBA reconstruction that the fit's surface draws at the identity viewport (alpha 1
// on covered pixels, 0 elsewhere): what the least squares minimised the error of.
Raster ReconstructRaster(const ColorFit& fit);

// True where pixel (x, y) of target belongs to the fitting domain (see FitColors).
bool InDomain(const Raster& target, const Raster* mask, int x, int y);

}  // namespace sdvi
