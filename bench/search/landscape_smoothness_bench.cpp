// How learnable is a plateau landscape from few samples? The criterion that fixes the smoothness of
// family (a) (bench/search/README.md) without involving any search algorithm: a GP (search/src/gaussian_process.h,
// Matérn 5/2 ARD, plain maximum likelihood within the default bounds) fitted to N uniform random
// samples of the squashed trend must explain median R² ≥ 0.5 of it, measured on 2000 fresh uniform
// points, over landscapes × 2 feature dimensions. Also reports R² of the quantised feature itself and
// the number of distinct strategies in the box (2000 samples, threshold 0.05), so a smoother trend
// can be seen to keep enough strategies.
//
// Usage: search_landscape_smoothness_bench [--family plateaus] [--frequencies 1.5,1,0.75,0.5]
//          [--first-landscape 1001] [--landscapes 20] [--samples 20] [--dim 3] [--regions 6]
//          (a frequency of 0 is the family's own bound)
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_args.h"
#include "gaussian_process.h"
#include "landscape_model.h"
#include "podium/search/search.h"
#include "podium/search/strategies.h"

using podium::tasks::landscape::LandscapeModel;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// R² of a GP fitted to (x, y) at predicting the test targets.
double r_squared(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::MatrixXd& test_x, const Eigen::VectorXd& test_y,
                 podium::base::Rng& rng) {
  podium::search::GaussianProcess gp(static_cast<int>(x.cols()), 0.5);
  gp.set(x, y, gp.default_theta());
  gp.fit(rng, 4, podium::search::GpBounds{});
  double sse = 0.0, sst = 0.0;
  const double mean = test_y.mean();
  for (Eigen::Index i = 0; i < test_x.rows(); ++i) {
    double m = 0.0, var = 0.0;
    gp.predict(test_x.row(i).transpose(), m, var);
    sse += (m - test_y[i]) * (m - test_y[i]);
    sst += (test_y[i] - mean) * (test_y[i] - mean);
  }
  return 1.0 - sse / sst;
}
}  // namespace

int main(int argc, char** argv) {
  std::string family = "plateaus";
  std::vector<double> frequencies = {1.5, 1.0, 0.75, 0.5};
  int first = 1001, landscapes = 20, samples = 20, dim = 3, regions = 6;
  // Counts within [min, max]: dim and regions as the landscape task allows them, the rest small
  // enough that first + landscapes stays an int.
  using podium::bench::checked, podium::bench::count, podium::bench::Flag;
  const auto read = [&](const std::string& key, const char* value) {
    if (key == "--family") family = value;
    else if (key == "--frequencies")
      return checked(podium::bench::list(value, frequencies,
                                         [](const char* f, double& v) { return podium::bench::real_number(f, v) && v >= 0; }));
    else if (key == "--first-landscape") return checked(count(value, 0, 1'000'000'000, first));
    else if (key == "--landscapes") return checked(count(value, 1, 1'000'000, landscapes));
    else if (key == "--samples") return checked(count(value, 1, 1'000'000, samples));
    else if (key == "--dim") return checked(count(value, 1, 1000, dim));
    else if (key == "--regions") return checked(count(value, 2, 10'000, regions));
    else return Flag::unknown;
    return Flag::read;
  };
  if (!podium::bench::read_flags(argc, argv,
                                 "[--family F] [--frequencies F,... ≥ 0] [--first-landscape N ≥ 0] [--landscapes N ≥ 1] "
                                 "[--samples N ≥ 1] [--dim 1..1000] [--regions 2..10000]",
                                 read))
    return 2;
  try {  // a bad family name, reported here rather than thrown from the loop below
    (void)LandscapeModel(podium::tasks::landscape::LandscapeOptions{family, dim, static_cast<std::uint64_t>(first), regions});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: --family %s: %s\n", argv[0], family.c_str(), e.what());
    return 2;
  }
  const auto features = podium::search::Feature::list_from_json(
      podium::search::Json::parse(R"([{"name": "f0", "low": 0, "high": 1}, {"name": "f1", "low": 0, "high": 1}])"), "features");
  std::printf("family %s, landscapes %d..%d, %d samples, dim %d, regions %d\n", family.c_str(), first, first + landscapes - 1,
              samples, dim, regions);
  std::printf("max frequency | median R² trend | median R² feature | strategies in box\n");
  bool any_pass = false;
  for (double frequency : frequencies) {
    std::vector<double> r2_trend, r2_feature, strategies;
    for (int l = first; l < first + landscapes; ++l) {
      podium::tasks::landscape::LandscapeOptions options{family, dim, static_cast<std::uint64_t>(l), regions};
      options.max_frequency = frequency;
      const LandscapeModel model(options);
      podium::base::Rng rng(podium::base::derive_seed(static_cast<std::uint64_t>(l), 0x5a0071));
      auto sample = [&](int n, Eigen::MatrixXd& x, std::vector<std::vector<double>>& trend,
                        std::vector<std::vector<double>>& feature) {
        x.resize(n, dim);
        for (int i = 0; i < n; ++i) {
          std::vector<double> p(static_cast<std::size_t>(dim));
          for (auto& v : p) v = rng.uniform();
          x.row(i) = Eigen::Map<const Eigen::VectorXd>(p.data(), dim).transpose();
          trend.push_back(model.trend(p));
          feature.push_back(model.feature(p));
        }
      };
      Eigen::MatrixXd x, test_x;
      std::vector<std::vector<double>> trend, feature, test_trend, test_feature;
      sample(samples, x, trend, feature);
      sample(2000, test_x, test_trend, test_feature);
      for (int f = 0; f < LandscapeModel::kFeatureDim; ++f) {
        auto column = [&](const std::vector<std::vector<double>>& rows) {
          Eigen::VectorXd c(static_cast<Eigen::Index>(rows.size()));
          for (std::size_t i = 0; i < rows.size(); ++i) c[static_cast<Eigen::Index>(i)] = rows[i][static_cast<std::size_t>(f)];
          return c;
        };
        r2_trend.push_back(r_squared(x, column(trend), test_x, column(test_trend), rng));
        r2_feature.push_back(r_squared(x, column(feature), test_x, column(test_feature), rng));
      }
      strategies.push_back(podium::search::count_strategies(features, test_feature, 0.05));
    }
    const double m = median(r2_trend);
    any_pass = any_pass || m >= 0.5;
    std::printf("%13.2f | %15.2f | %17.2f | %.0f (median)\n", frequency, m, median(r2_feature), median(strategies));
  }
  std::printf("criterion (median R² of the trend >= 0.5): %s\n", any_pass ? "met by at least one bound" : "not met");
  return 0;
}
