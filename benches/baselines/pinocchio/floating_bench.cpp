// Pinocchio's side of the floating-base benchmark (benches/floating_robot.py): a URDF
// loaded with JointModelFreeFlyer, the joints named after it locked at q = 0, then crba,
// nonLinearEffects, crba + nonLinearEffects, rnea, aba, ccrba, computeRNEADerivatives and
// computeABADerivatives timed over 1000 random
// states (random unit quaternion and position, joints uniform in their limits, v in
// (-2, 2), a in (-5, 5), tau in (-20, 20)) in 11 rounds; prints {routine: {median_ns,
// min_ns}} as JSON. Built by build.sh next to panda_bench.
//
// Usage: floating_bench ROBOT.urdf [LOCKED_JOINT ...]
#include <pinocchio/parsers/urdf.hpp>

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/centroidal.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

using pinocchio::Data;
using pinocchio::Model;
using Eigen::VectorXd;

namespace {

volatile double g_sink = 0.0;

inline void clobber() { asm volatile("" : : : "memory"); }

template<typename F>
double time_loop(F & f, std::size_t n)
{
  double acc = 0.0;
  clobber();
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < n; ++k)
  {
    acc += f(k);
    clobber();
  }
  const auto t1 = std::chrono::steady_clock::now();
  g_sink = g_sink + acc;
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / double(n);
}

} // namespace

int main(int argc, char ** argv)
{
  if (argc < 2)
  {
    std::fprintf(stderr, "usage: floating_bench ROBOT.urdf [LOCKED_JOINT ...]\n");
    return 2;
  }
  Model full;
  pinocchio::urdf::buildModel(argv[1], pinocchio::JointModelFreeFlyer(), full);
  std::vector<pinocchio::JointIndex> lock;
  for (int i = 2; i < argc; ++i)
  {
    const auto j = full.getJointId(argv[i]);
    if (j >= (pinocchio::JointIndex)full.njoints)
    {
      std::fprintf(stderr, "no joint %s\n", argv[i]);
      return 2;
    }
    lock.push_back(j);
  }
  const Model model =
    lock.empty() ? full : pinocchio::buildReducedModel(full, lock, pinocchio::neutral(full));
  if (model.nq != model.nv + 1)
  {
    std::fprintf(stderr, "unexpected nq=%d nv=%d\n", model.nq, model.nv);
    return 2;
  }
  std::fprintf(stderr, "model: nq=%d nv=%d\n", model.nq, model.nv);
  constexpr std::size_t N = 1000;
  constexpr int ROUNDS = 11;
  std::mt19937_64 rng(20261128ULL);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<VectorXd> Q(N), V(N), A(N), T(N);
  const int nv = model.nv;
  for (std::size_t k = 0; k < N; ++k)
  {
    Q[k].resize(model.nq);
    V[k].resize(nv);
    A[k].resize(nv);
    T[k].resize(nv);
    for (int i = 0; i < 3; ++i)
      Q[k][i] = -1.0 + 2.0 * u01(rng);
    Eigen::Vector4d quat(normal(rng), normal(rng), normal(rng), normal(rng));
    Q[k].segment<4>(3) = quat.normalized();
    for (int i = 7; i < model.nq; ++i)
    {
      const double lo = model.lowerPositionLimit[i], hi = model.upperPositionLimit[i];
      Q[k][i] = lo + (hi - lo) * u01(rng);
    }
    for (int i = 0; i < nv; ++i)
    {
      V[k][i] = -2.0 + 4.0 * u01(rng);
      A[k][i] = -5.0 + 10.0 * u01(rng);
      T[k][i] = -20.0 + 40.0 * u01(rng);
    }
  }
  Data data(model);
  const int last = nv - 1;
  auto crba = [&](std::size_t k) {
    pinocchio::crba(model, data, Q[k]);
    return data.M(0, last) + data.M(last, last);
  };
  auto nle = [&](std::size_t k) {
    pinocchio::nonLinearEffects(model, data, Q[k], V[k]);
    return data.nle[0] + data.nle[last];
  };
  auto crba_nle = [&](std::size_t k) {
    pinocchio::crba(model, data, Q[k]);
    pinocchio::nonLinearEffects(model, data, Q[k], V[k]);
    return data.M(0, last) + data.nle[last];
  };
  auto rnea = [&](std::size_t k) {
    pinocchio::rnea(model, data, Q[k], V[k], A[k]);
    return data.tau[0] + data.tau[last];
  };
  auto aba = [&](std::size_t k) {
    pinocchio::aba(model, data, Q[k], V[k], T[k]);
    return data.ddq[0] + data.ddq[last];
  };
  auto ccrba = [&](std::size_t k) {
    pinocchio::ccrba(model, data, Q[k], V[k]);
    return data.Ag(0, last) + data.Ag(5, last);
  };
  auto rnea_derivatives = [&](std::size_t k) {
    pinocchio::computeRNEADerivatives(model, data, Q[k], V[k], A[k]);
    return data.dtau_dq(0, last) + data.dtau_dv(last, 0);
  };
  auto aba_derivatives = [&](std::size_t k) {
    pinocchio::computeABADerivatives(model, data, Q[k], V[k], T[k]);
    return data.ddq_dq(0, last) + data.ddq_dv(last, 0) + data.Minv(0, last);
  };
  struct Routine
  {
    const char * name;
    std::function<double(std::size_t)> f;
  };
  std::vector<Routine> routines = {
    {"crba", crba}, {"nonLinearEffects", nle}, {"crba+nonLinearEffects", crba_nle},
    {"rnea", rnea}, {"aba", aba},               {"ccrba", ccrba},
    {"computeRNEADerivatives", rnea_derivatives}, {"computeABADerivatives", aba_derivatives}};
  for (auto & r : routines)
    time_loop(r.f, N);
  std::printf("{");
  for (std::size_t i = 0; i < routines.size(); ++i)
  {
    std::vector<double> t;
    for (int round = 0; round < ROUNDS; ++round)
      t.push_back(time_loop(routines[i].f, N));
    std::sort(t.begin(), t.end());
    std::printf("%s\"%s\": {\"median_ns\": %.1f, \"min_ns\": %.1f}", i ? ", " : "",
                routines[i].name, t[ROUNDS / 2], t[0]);
  }
  std::printf("}\n");
  return 0;
}
