#include "podium/learn/learner.h"

#include <dlfcn.h>

#include <mutex>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/native_blas.h"
#include "podium/learn/ppo.h"
#include "podium/learn/sac.h"

namespace podium::learn {

namespace {

// Applies `overrides` on top of a preset's JSON, so unknown fields are still reported.
base::Json merged(base::Json preset, const base::Json& overrides) {
  for (const auto& [key, value] : overrides.items()) preset[key] = value;
  return preset;
}

}  // namespace

std::unique_ptr<Learner> make_learner(const base::Json& spec, const BoxSpace& observation_space, const BoxSpace& action_space,
                                      std::uint64_t seed) {
  base::ConfigReader r(spec, "", "learner spec");
  const std::string algorithm = r.choice("algorithm", base::required, {"ppo", "sac"});
  const std::string preset = r.choice("preset", "quick", {"quick", "paper"});
  const base::Json overrides = r.raw_object("config");
  r.finish();
  if (algorithm == "sac") {
    const SacConfig base_config = preset == "paper" ? SacConfig::paper() : SacConfig::quick();
    return std::make_unique<Sac>(SacConfig::from_json(merged(base_config.to_json(), overrides)), observation_space, action_space,
                                 seed);
  }
  const PpoConfig base_config = preset == "paper" ? PpoConfig::paper() : PpoConfig{};  // "ppo", the other choice
  return std::make_unique<Ppo>(PpoConfig::from_json(merged(base_config.to_json(), overrides)), observation_space, action_space,
                               seed);
}

std::vector<double> evaluate(Learner& learner, Env& env, int episodes, bool deterministic) {
  std::vector<double> returns;
  std::vector<double> observation;
  std::vector<double> action(env.action_space().size());
  StepResult result;
  for (int e = 0; e < episodes; ++e) {
    env.reset(observation);
    double total = 0.0;
    do {
      learner.act(observation, action, deterministic, env.action_scale());
      env.step(action, result);
      total += result.reward;
      observation = result.observation;
    } while (!result.terminated && !result.truncated);
    returns.push_back(total);
  }
  return returns;
}

std::string active_blas_library() {
  void* symbol = dlsym(RTLD_DEFAULT, "sgemm_");
  Dl_info info{};
  if (symbol == nullptr || dladdr(symbol, &info) == 0 || info.dli_fname == nullptr) return "";
  std::error_code ec;
  const auto resolved = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::string(info.dli_fname) : resolved.string();
}

bool is_reference_blas(const std::string& library_path) { return library_path.find("/blas/libblas.so") != std::string::npos; }

void setup_blas() {
  static std::once_flag once;
  std::call_once(once, [] {
    using SetThreads = void (*)(int);
    if (auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) set(1);
    const std::string blas = active_blas_library();
    if (is_reference_blas(blas))
      base::log_warning("learn: the reference BLAS (" + blas +
                        ") is active; network updates are 7-9x slower than with OpenBLAS. Fix: "
                        "apt-get install libopenblas0-pthread, or update-alternatives --config "
                        "libblas.so.3-x86_64-linux-gnu");
    const std::string core = base::openblas_core_name();
    const std::string wider = base::openblas_core_override(core, base::cpu_vector_bits());
    if (!wider.empty())
      base::log_warning("learn: OpenBLAS runs its generic " + core +
                        " kernels on this CPU (a model newer than it knows); "
                        "network updates are about 2x slower. Fix: OPENBLAS_CORETYPE=" +
                        wider + " in the environment (the podium program sets it itself)");
  });
}

}  // namespace podium::learn
