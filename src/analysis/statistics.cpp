// Ensemble statistics: means, correlations, logarithmic binning and the two fits.
#include "unjam/analysis/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace unjam {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double Mean(const std::vector<double>& samples) {
  double sum = 0.0;
  for (const double s : samples) sum += s;
  return sum / static_cast<double>(samples.size());
}

// Σ (a − mean_a)(b − mean_b): two passes, so that a large common offset does not cancel
// the small deviations the way Σ ab − n·mean_a·mean_b would.
double CenteredCrossSum(const std::vector<double>& a, double mean_a, const std::vector<double>& b,
                        double mean_b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += (a[k] - mean_a) * (b[k] - mean_b);
  return sum;
}

void CheckSameSize(std::size_t a, std::size_t b, const char* what) {
  if (a != b) {
    throw std::invalid_argument(std::string(what) + ": sizes differ (" + std::to_string(a) +
                                " vs " + std::to_string(b) + ")");
  }
}

// Number of log bins between r_min and r_max. A ratio that is an exact number of bins
// (e.g. three decades) must not gain a spurious extra bin from rounding in log10.
int LogBinCount(double r_min, double r_max, int bins_per_decade) {
  const double exact = bins_per_decade * std::log10(r_max / r_min);
  const double nearest = std::round(exact);
  const double count =
      std::abs(exact - nearest) < 1e-9 * std::max(1.0, exact) ? nearest : std::ceil(exact);
  return std::max(1, static_cast<int>(count));
}

// The bin holding r, found among the stored edges so that it always agrees with them
// (floor of a log10 may be off by one right at an edge).
int LogBinIndex(double r, const std::vector<double>& edges) {
  const int bins = static_cast<int>(edges.size()) - 1;
  const auto upper = std::upper_bound(edges.begin(), edges.end(), r);
  const int k = static_cast<int>(upper - edges.begin()) - 1;
  return std::clamp(k, 0, bins - 1);
}

double Median(std::vector<double> values) {
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  if (values.size() % 2 == 1) return values[mid];
  const double upper = values[mid];
  const double lower = *std::max_element(values.begin(), values.begin() + mid);
  return 0.5 * (lower + upper);
}

struct LogPoint {
  double x = 0.0;       // log r
  double y = 0.0;       // log value
  double weight = 0.0;  // 1 / σ² of y; 0 until known
};

std::vector<LogPoint> PointsToFit(const std::vector<LogBin>& bins, double fit_min, double fit_max) {
  std::vector<LogPoint> points;
  for (const LogBin& bin : bins) {
    if (bin.count <= 0 || !(bin.mean > 0.0) || !(bin.r_mean > 0.0)) continue;
    if (bin.r_mean < fit_min || bin.r_mean > fit_max) continue;
    const double sigma = bin.error / bin.mean;  // error of log(mean), to first order
    points.push_back(
        {std::log(bin.r_mean), std::log(bin.mean), sigma > 0.0 ? 1.0 / (sigma * sigma) : 0.0});
  }
  return points;
}

// Bins whose error is zero (a single sample, or identical samples) carry no information on
// their scatter: give them a typical weight rather than an infinite one.
void FillMissingWeights(std::vector<LogPoint>& points) {
  std::vector<double> known;
  for (const LogPoint& p : points) {
    if (p.weight > 0.0 && std::isfinite(p.weight)) known.push_back(p.weight);
  }
  const double fallback = known.empty() ? 1.0 : Median(known);
  for (LogPoint& p : points) {
    if (!(p.weight > 0.0) || !std::isfinite(p.weight)) p.weight = fallback;
  }
}

}  // namespace

MeanAndError MeanWithError(const std::vector<double>& samples) {
  MeanAndError out;
  out.count = static_cast<int>(samples.size());
  if (samples.empty()) return out;
  out.mean = Mean(samples);
  if (out.count < 2) return out;
  const double variance = CenteredCrossSum(samples, out.mean, samples, out.mean) / (out.count - 1);
  out.error = std::sqrt(variance / out.count);
  return out;
}

double PearsonCorrelation(const std::vector<double>& x, const std::vector<double>& y) {
  CheckSameSize(x.size(), y.size(), "PearsonCorrelation");
  if (x.size() < 2) return 0.0;
  const double mean_x = Mean(x);
  const double mean_y = Mean(y);
  const double sxx = CenteredCrossSum(x, mean_x, x, mean_x);
  const double syy = CenteredCrossSum(y, mean_y, y, mean_y);
  if (!(sxx > 0.0) || !(syy > 0.0)) return 0.0;
  const double r = CenteredCrossSum(x, mean_x, y, mean_y) / std::sqrt(sxx * syy);
  // Rounding may push a perfect correlation a hair beyond ±1.
  return std::clamp(r, -1.0, 1.0);
}

std::vector<LogBin> LogBinned(const std::vector<double>& r, const std::vector<double>& value,
                              double r_min, double r_max, int bins_per_decade) {
  CheckSameSize(r.size(), value.size(), "LogBinned");
  if (!(r_min > 0.0) || !(r_max > r_min) || !std::isfinite(r_max) || bins_per_decade < 1) {
    throw std::invalid_argument("LogBinned: need 0 < r_min < r_max and bins_per_decade >= 1");
  }
  const int bins = LogBinCount(r_min, r_max, bins_per_decade);
  std::vector<double> edges(bins + 1);
  for (int k = 0; k <= bins; ++k)
    edges[k] = r_min * std::pow(10.0, static_cast<double>(k) / bins_per_decade);
  // The last bin stops at r_max: samples beyond it are ignored, so that is its true extent.
  edges[bins] = r_max;

  std::vector<std::vector<double>> values(bins);
  std::vector<double> r_sum(bins, 0.0);
  for (std::size_t s = 0; s < r.size(); ++s) {
    if (!(r[s] >= r_min) || !(r[s] < r_max)) continue;  // also drops NaN
    const int k = LogBinIndex(r[s], edges);
    values[k].push_back(value[s]);
    r_sum[k] += r[s];
  }

  std::vector<LogBin> out(bins);
  for (int k = 0; k < bins; ++k) {
    LogBin& bin = out[k];
    bin.r_low = edges[k];
    bin.r_high = edges[k + 1];
    const MeanAndError stats = MeanWithError(values[k]);
    bin.count = stats.count;
    bin.mean = stats.mean;
    bin.error = stats.error;
    bin.r_mean = bin.count > 0 ? r_sum[k] / bin.count : 0.0;
  }
  return out;
}

PowerLawFit FitPowerLaw(const std::vector<LogBin>& bins, double fit_min, double fit_max) {
  PowerLawFit fit;
  fit.fit_min = fit_min;
  fit.fit_max = fit_max;
  std::vector<LogPoint> points = PointsToFit(bins, fit_min, fit_max);
  fit.points = static_cast<int>(points.size());
  if (fit.points < 3) {
    fit.alpha = fit.alpha_error = fit.prefactor = kNaN;
    return fit;
  }
  FillMissingWeights(points);

  double w_sum = 0.0, x_mean = 0.0, y_mean = 0.0;
  for (const LogPoint& p : points) {
    w_sum += p.weight;
    x_mean += p.weight * p.x;
    y_mean += p.weight * p.y;
  }
  x_mean /= w_sum;
  y_mean /= w_sum;
  double sxx = 0.0, sxy = 0.0;
  for (const LogPoint& p : points) {
    sxx += p.weight * (p.x - x_mean) * (p.x - x_mean);
    sxy += p.weight * (p.x - x_mean) * (p.y - y_mean);
  }
  if (!(sxx > 0.0)) {  // all points at the same r: no slope
    fit.alpha = fit.alpha_error = fit.prefactor = kNaN;
    return fit;
  }
  const double slope = sxy / sxx;
  const double intercept = y_mean - slope * x_mean;
  // Scale the weights by the observed scatter (reduced χ²) rather than trusting them: the
  // bin errors of correlated ensemble data are often off by a constant factor.
  double chi2 = 0.0;
  for (const LogPoint& p : points) {
    const double residual = p.y - (intercept + slope * p.x);
    chi2 += p.weight * residual * residual;
  }
  const double scatter = chi2 / (fit.points - 2);
  fit.alpha = -slope;
  fit.alpha_error = std::sqrt(scatter / sxx);
  fit.prefactor = std::exp(intercept);
  return fit;
}

ExponentialTailFit FitExponentialTail(const std::vector<double>& samples, double threshold) {
  ExponentialTailFit fit;
  fit.threshold = threshold;
  double excess = 0.0;
  for (const double s : samples) {
    if (s > threshold) {
      excess += s - threshold;
      ++fit.count;
    }
  }
  if (fit.count == 0) {
    fit.scale = fit.scale_error = kNaN;
    return fit;
  }
  fit.scale = excess / fit.count;
  fit.scale_error = fit.scale / std::sqrt(static_cast<double>(fit.count));
  return fit;
}

Histogram MakeHistogram(const std::vector<double>& samples, double low, double high, int bins) {
  // A range so narrow that its bins' width underflows to 0 would index bins by NaN.
  if (bins < 1 || !(high > low) || !std::isfinite(low) || !std::isfinite(high) ||
      !((high - low) / bins > 0.0)) {
    throw std::invalid_argument(
        "MakeHistogram: need low < high (finite, bins of positive width) and bins >= 1");
  }
  Histogram h;
  h.low = low;
  h.high = high;
  h.counts.assign(bins, 0);
  h.density.assign(bins, 0.0);
  const double width = (high - low) / bins;
  for (const double s : samples) {
    if (!(s >= low) || !(s < high)) {  // also counts NaN as outside
      ++h.outside;
      continue;
    }
    // Rounding may put a sample just below `high` one past the last bin.
    const int k = std::min(bins - 1, static_cast<int>((s - low) / width));
    ++h.counts[k];
  }
  if (samples.empty()) return h;
  const double n = static_cast<double>(samples.size());
  for (int k = 0; k < bins; ++k) h.density[k] = h.counts[k] / (n * width);
  return h;
}

}  // namespace unjam
