// Ensemble statistics of perturbation responses: means with standard errors, correlations,
// logarithmic binning of a field against distance, and the two fits the physics asks for
// (a power-law decay of the displacement field, an exponential tail of the critical-force
// distribution). Pure functions of numbers: no scene, no solver.
#pragma once

#include <vector>

namespace unjam {

// Mean and standard error of the mean (sample standard deviation / √n; 0 when n < 2).
struct MeanAndError {
  double mean = 0.0;
  double error = 0.0;
  int count = 0;
};
MeanAndError MeanWithError(const std::vector<double>& samples);

// Pearson correlation coefficient of (x, y); 0 when either has zero variance or n < 2.
// Throws std::invalid_argument if the sizes differ.
double PearsonCorrelation(const std::vector<double>& x, const std::vector<double>& y);

// Values binned in logarithmically spaced bins of a positive coordinate r.
struct LogBin {
  double r_low = 0.0, r_high = 0.0;  // bin edges
  double r_mean = 0.0;               // mean r of the samples in the bin
  double mean = 0.0;                 // mean value
  double error = 0.0;                // standard error of the mean value
  int count = 0;
};
// Bins [r_min, r_max) into `bins_per_decade` bins per decade; samples outside, or with
// r ≤ 0, are ignored. Empty bins are kept (count 0) so that the layout is fixed.
std::vector<LogBin> LogBinned(const std::vector<double>& r, const std::vector<double>& value,
                              double r_min, double r_max, int bins_per_decade);

// y ∝ x^(−alpha): least squares of log y on log x over the bins with count > 0, mean > 0
// and r_mean in [fit_min, fit_max], weighted by 1/σ² of log y (σ = error/mean; bins with
// zero error get the median weight). `alpha_error` is the standard error of the slope
// (from the weighted residual scatter, so that it is honest when the weights are off).
struct PowerLawFit {
  double alpha = 0.0;
  double alpha_error = 0.0;
  double prefactor = 0.0;  // y = prefactor · x^(−alpha)
  double fit_min = 0.0, fit_max = 0.0;
  int points = 0;  // bins used; < 3 means no fit (alpha = NaN)
};
PowerLawFit FitPowerLaw(const std::vector<LogBin>& bins, double fit_min, double fit_max);

// Tail P(x > s) ∝ exp(−s / scale) of positive samples above `threshold`: maximum likelihood
// for the shifted exponential (scale = mean(x − threshold) over x > threshold), error
// scale / √n. NaN scale and zero count when no sample is above the threshold.
struct ExponentialTailFit {
  double scale = 0.0;
  double scale_error = 0.0;
  double threshold = 0.0;
  int count = 0;
};
ExponentialTailFit FitExponentialTail(const std::vector<double>& samples, double threshold);

// Histogram of samples on `bins` equal bins over [low, high): probability density
// (count / (n · width)) per bin; samples outside are counted in `outside`.
struct Histogram {
  double low = 0.0, high = 0.0;
  std::vector<double> density;
  std::vector<int> counts;
  int outside = 0;
};
Histogram MakeHistogram(const std::vector<double>& samples, double low, double high, int bins);

}  // namespace unjam
