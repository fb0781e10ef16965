#pragma once
// The dominant frequency of a sampled signal, for the lateral and tilt oscillations of a settling
// body (docs/analysis.md).
#include <vector>

namespace settle::analysis {

/// The dominant frequency of a (possibly vector) signal: the peak of the summed power spectra
/// of its components, each with its Hann-weighted mean removed and a Hann window applied,
/// after linear resampling onto a uniform grid of min(n, 4096) points. The peak bin is refined
/// by maximising the windowed Fourier transform between its neighbours (golden section), so the
/// frequency is not limited to the bin spacing 1/T.
struct SpectralPeak {
  /// false for fewer than 4 samples or a constant signal (fluctuations below 1e-12 of its
  /// largest value: round-off)
  bool found = false;
  double frequency_hz = 0.0;
  /// Fraction of the fluctuation power in the bins within two bins of the peak (the main lobe
  /// of the Hann window: about 1 for a sinusoid, small for broadband signals).
  double concentration = 0.0;
  double cycles = 0.0;  ///< frequency times the signal's duration
};
SpectralPeak spectral_peak(const std::vector<double>& t_si, const std::vector<std::vector<double>>& components);

}  // namespace settle::analysis
