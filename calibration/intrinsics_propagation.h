// The measuring camera's intrinsics, estimated with an uncertainty
// (`layerlab camera-intrinsics`, camera_model.h), carry into the fit: every
// marker's angle comes through them, so their error is shared by all markers,
// which the fit's covariance (independent marker noise) leaves out.
#pragma once

#include "layerlab/calibration/calibration.h"

namespace layerlab {

// Propagated by refitting: each intrinsic moved by one standard deviation,
// the markers' angles read again from their camera pixels, the geometry
// fitted again with report->options; each parameter's changes add in
// quadrature to its standard deviation (the intrinsics independent, as
// OpenCV reports them), and a note says how much the largest grew. Nothing
// when the camera has no uncertainty or no marker gives a camera pixel.
void PropagateIntrinsicsUncertainty(const DisplaySystem& system, const Measurements& measurements,
                                    CalibrationReport* report);

}  // namespace layerlab
