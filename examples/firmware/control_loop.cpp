// A fixed-rate control loop: every SysTick (1 kHz) the controller reads the simulated robot's
// state and computes torques by computed-torque control,
//   tau = M(q) (qdd_ref + Kp (q_ref - q) - Kd v) + h(q, v)        (crba and nle)
// and the simulator advances the robot one step with those torques,
//   qdd = aba(q, v, tau); v += dt qdd; q += dt v                   (semi-implicit Euler)
// Since the controller's model is the simulator's, the error obeys e'' + Kd e' + Kp e = 0 up to
// the step's discretisation: with Kp = 100, Kd = 20 it falls by e^-10 (times 11) in a second.
// From 0.5 rad that is 2.5e-4 rad after one second. Prints the largest joint error every 100 ms
// and exits with status 0 if it fell below 5e-4 rad after one second, 1 otherwise.
#include DYNGEN_HEADER

extern "C" void sh_write(const char* text);
extern "C" void sh_exit(int code);

namespace {

namespace robot = DYNGEN_NAMESPACE;
using Scalar = SCALAR;

constexpr Scalar dt = Scalar(0.001);
constexpr Scalar kp = 100, kd = 20;
constexpr int ticks = 1000;

Scalar q[robot::nq], v[robot::nv];  // the simulated robot: at rest at q = 0
Scalar q_ref[robot::nq];            // where the controller takes it
volatile int tick = 0;

/// "label value" with value printed as an integer count of micro-units.
void print_micro(const char* label, Scalar value) {
  char line[64];
  char* out = line;
  for (const char* c = label; *c != 0; ++c) *out++ = *c;
  long micro = static_cast<long>(value * Scalar(1e6));
  if (micro < 0) *out++ = '-', micro = -micro;
  char digits[20];
  int n = 0;
  do digits[n++] = static_cast<char>('0' + micro % 10);
  while ((micro /= 10) != 0);
  while (n > 0) *out++ = digits[--n];
  for (const char* c = " (1e-6)\n"; *c != 0; ++c) *out++ = *c;
  *out = 0;
  sh_write(line);
}

Scalar largest_error() {
  Scalar e = 0;
  for (int k = 0; k < robot::nq; ++k) {
    const Scalar d = q_ref[k] > q[k] ? q_ref[k] - q[k] : q[k] - q_ref[k];
    if (d > e) e = d;
  }
  return e;
}

/// One control period: the controller, then the simulator.
void step() {
  Scalar M[robot::nv * robot::nv], h[robot::nv], u[robot::nv], tau[robot::nv], qdd[robot::nv];
  robot::crba(q, M);
  robot::nle(q, v, h);
  for (int i = 0; i < robot::nv; ++i) u[i] = kp * (q_ref[i] - q[i]) - kd * v[i];
  for (int i = 0; i < robot::nv; ++i) {
    Scalar sum = h[i];
    for (int j = 0; j < robot::nv; ++j) sum += M[i * robot::nv + j] * u[j];
    tau[i] = sum;
  }
  robot::aba(q, v, tau, qdd);
  for (int i = 0; i < robot::nv; ++i) {
    v[i] += dt * qdd[i];
    q[i] += dt * v[i];
  }
}

}  // namespace

extern "C" void systick_handler() { tick = tick + 1; }

int main() {
  static_assert(robot::nq == robot::nv, "the example takes robots without free joints");
  for (int k = 0; k < robot::nq; ++k) q_ref[k] = Scalar(0.5) - Scalar(0.2) * Scalar(k % 4);
  // SysTick at 1 kHz from the 25 MHz core clock of qemu's mps2 boards
  volatile unsigned* const systick = reinterpret_cast<volatile unsigned*>(0xE000E010u);
  systick[1] = 25000 - 1;  // LOAD
  systick[2] = 0;          // VAL
  systick[0] = 7;          // CTRL: core clock, interrupt, enable
  print_micro("t = 0 ms, largest joint error ", largest_error());
  for (int done = 0; done < ticks;) {
    __asm__ volatile("wfi");
    if (tick == done) continue;  // woken by something else
    done = done + 1;
    step();
    if (done % 100 == 0) {
      char label[48];  // filled by hand: an initialiser would zero the rest with memset
      int at = 0;
      for (const char* c = "t = "; *c != 0; ++c) label[at++] = *c;
      for (int divisor = 1000; divisor > 0; divisor /= 10)
        if (done >= divisor || divisor == 1) label[at++] = static_cast<char>('0' + done / divisor % 10);
      for (const char* c = " ms, largest joint error "; *c != 0; ++c) label[at++] = *c;
      label[at] = 0;
      print_micro(label, largest_error());
    }
  }
  systick[0] = 0;
  return largest_error() < Scalar(5e-4) ? 0 : 1;
}
