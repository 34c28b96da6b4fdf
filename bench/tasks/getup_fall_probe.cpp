// What the fall's actions change in the get-up's start poses: falls of the task's default
// environment (the seed repository's body) with zero torque during the fall (the repository's
// env.py) and with §7's N(0, 0.1) actions, from the same seeds: the share that ends on the back,
// the mean COM and head-top heights at the fall's end, and the mean joint-angle distance between
// the two ends of each seed. Run:
//   build/bin/getup_fall_probe [FALLS]
#include <cstdio>
#include <memory>
#include <vector>

#include "bench_args.h"
#include "getup_env.h"

using namespace podium;

namespace {

struct Ends {
  int on_back = 0;
  double com_m = 0.0, head_m = 0.0;
  std::vector<Eigen::VectorXd> q;
};

Ends fall_ends(double sigma, long long falls) {
  tasks::getup::EnvSettings settings;
  settings.fall.action_sigma = sigma;
  tasks::getup::GetupEnv env(settings, std::make_shared<double>(1.0), false);
  std::vector<double> observation;
  Ends ends;
  for (long long k = 0; k < falls; ++k) {
    env.seed(5000 + static_cast<std::uint64_t>(k));
    env.reset(observation);
    ends.on_back += tasks::getup::lies_on_back(env);
    ends.com_m += env.features().com.z() / static_cast<double>(falls);
    ends.head_m += env.weak().head_height_m / static_cast<double>(falls);
    ends.q.push_back(env.world().data().q);
  }
  return ends;
}

}  // namespace

int main(int argc, char** argv) {
  long long falls = 200;
  if (argc > 2 || (argc == 2 && !bench::whole_number(argv[1], 1, falls))) {
    std::fprintf(stderr, "usage: %s [FALLS>0]\n", argv[0]);
    return 2;
  }
  const Ends zero = fall_ends(0.0, falls), noisy = fall_ends(0.1, falls);
  std::printf("%lld falls        on back  COM (m)  head top (m)\n", falls);
  std::printf("zero torque      %-8d %-8.3f %.3f\n", zero.on_back, zero.com_m, zero.head_m);
  std::printf("N(0, 0.1)        %-8d %-8.3f %.3f\n", noisy.on_back, noisy.com_m, noisy.head_m);
  double joints = 0.0;
  for (std::size_t k = 0; k < zero.q.size(); ++k)
    joints += (zero.q[k].tail(zero.q[k].size() - 7) - noisy.q[k].tail(noisy.q[k].size() - 7)).norm() / static_cast<double>(falls);
  std::printf("mean joint-angle distance between the two ends of a seed: %.3f rad\n", joints);
  return 0;
}
