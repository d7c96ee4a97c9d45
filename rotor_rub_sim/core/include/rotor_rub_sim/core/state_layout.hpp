// The methods' state vectors (model.hpp's modelling choices): the free
// layout (the rotor's station and the stator, their velocities, a motor
// drive's spin states, and the rotor model's own block after them:
// rotor_model.hpp), the state's kinematics as plain 2-vectors, and the
// modal block's helpers. The contact regime's layout, the rotor held on the
// bore, is constrained_dynamics.hpp's.
#pragma once

#include <Eigen/Core>

namespace rotor_rub::core {

using Vec2 = Eigen::Vector2d;

// The drive's states of a motor drive (unused with the prescribed drive).
struct SpinState {
  double angle_rad = 0.0;           // phi
  double speed_rad_per_s = 0.0;     // w = phi'
  double drive_integral_rad = 0.0;  // z: the speed controller's integrated speed error
};

// The drive's three states at the end of a method's state vector (kMotor
// only), after the positions and velocities: kBase is where they start.
template <bool kMotor, int kBase>
struct SpinLayout {
  static constexpr int kSpinSize = kMotor ? 3 : 0;
  static constexpr int kSpinAngle = kBase;          // phi [rad]
  static constexpr int kSpinSpeed = kBase + 1;      // w [rad/s]
  static constexpr int kDriveIntegral = kBase + 2;  // z [rad]
};

// A flexible rotor (flexible_rotor_model.hpp) carries its modal
// coordinates xi and their rates after a layout's fixed part: at most
// kMaxModalCoordinates of each (512 planar modes, the station's and 511 of
// the shaft's, in x/y pairs: the full FE model of a rotor of 256 nodes), in a
// state of dynamic size with that maximum (storage inside the vector, 16 kB:
// no allocation per step, test_allocations; Eigen copies only a state's
// rows, so a small model does not pay for the room). The bound keeps a method's
// call chain, a few tens of states on the stack, well inside a thread's
// stack; matrices of the state's size are allocated once, dense_rodasp.hpp.
inline constexpr int kMaxPlanarModes = 512;
inline constexpr int kMaxModalCoordinates = 2 * (kMaxPlanarModes - 1);
/// [xi; xi'] of a flexible rotor [sqrt(kg) m, sqrt(kg) m/s] (empty: the Jeffcott).
using ModalState = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 2 * kMaxModalCoordinates, 1>;

// The state vector of a flexible rotor's layouts: every one is one type,
// with room for the largest fixed part (an elastic stator under a motor: 11,
// rounded up to 12 so that the 12 + 2044 doubles are 16-byte aligned storage)
// and the modal block's maximum, so that a method's instances on one
// integrator (each stator, each drive, free flight and contact) share one set
// of Eigen and odeint instantiations, which shortens the flexible units'
// compile (docs/testing.md, "The longest compiles"). The free and contact
// states of a flexible rotor are thus one type: the layouts' indices, not the
// compiler, keep them apart.
inline constexpr int kMaxFixedStates = 12;
using FlexibleState = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxFixedStates + 2 * kMaxModalCoordinates, 1>;

// The rotor models (rotor_model.hpp): a layout's third parameter, whose
// State<kFixed> is the layout's state (fixed size without a modal block).
class JeffcottRotor;
class FlexibleRotor;

// Layout of the free (unconstrained) state vector. kStatorDof is 2 for an
// elastic stator and 0 for a rigid one; kMotor adds the drive's states;
// the rotor model its own block after them (kModal: a flexible rotor's xi,
// then xi', n each, n = modal_count()).
template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
struct FreeLayout : SpinLayout<kMotor, 2 * (2 + kStatorDof)> {
  static_assert(kStatorDof == 0 || kStatorDof == 2, "stator has 0 or 2 DOF");
  static constexpr int kDof = 2 + kStatorDof;
  static constexpr int kSize = 2 * kDof + SpinLayout<kMotor, 0>::kSpinSize;  // the fixed part
  static constexpr int kRotorPos = 0;          // x_r, y_r [m] (a flexible rotor's station)
  static constexpr int kStatorPos = 2;         // x_s, y_s [m] (elastic only)
  static constexpr int kRotorVel = kDof;       // x_r', y_r' [m/s]
  static constexpr int kStatorVel = kDof + 2;  // x_s', y_s' [m/s] (elastic only)
  static constexpr int kModal = kSize;         // the rotor's block: xi [sqrt(kg) m], then xi'
  using State = typename Rotor::template State<kSize>;
  static_assert(State::RowsAtCompileTime == Eigen::Dynamic || State::RowsAtCompileTime == kSize,
                "a fixed-size state is the layout's fixed part");
  static_assert(State::MaxRowsAtCompileTime >= kSize, "the state holds the layout's fixed part");
};

// A layout's state has a block when its size is dynamic.
template <class State>
inline constexpr bool kHasModalBlock = State::RowsAtCompileTime == Eigen::Dynamic;

// The modal coordinates in a state of layout L: how many (n), and the
// block [xi; xi'] (2 n entries from L::kModal).
template <class L, class State>
int modal_count(const State& x) {
  if constexpr (kHasModalBlock<State>) {
    return static_cast<int>(x.size() - L::kSize) / 2;
  } else {
    return 0;
  }
}
template <class L, class State>
ModalState modal_of(const State& x) {
  if constexpr (kHasModalBlock<State>) {
    return x.tail(x.size() - L::kSize);
  } else {
    return ModalState();
  }
}
// A state of layout L sized for a modal block (its fixed part unset).
template <class L>
typename L::State sized_state(const ModalState& modal) {
  typename L::State x;
  if constexpr (kHasModalBlock<typename L::State>) {
    x.resize(L::kSize + modal.size());
    x.tail(modal.size()) = modal;
  }
  return x;
}

// Positions and velocities of both bodies as plain 2-vectors (a rigid stator
// is at rest at the origin), and a motor drive's states.
struct Kinematics {
  Vec2 rotor_pos = Vec2::Zero();
  Vec2 rotor_vel = Vec2::Zero();
  Vec2 stator_pos = Vec2::Zero();
  Vec2 stator_vel = Vec2::Zero();
  SpinState spin;  // motor drive only
};

template <class L, class State>
void read_spin(const State& x, SpinState& spin) {
  if constexpr (L::kSpinSize > 0) {
    spin.angle_rad = x[L::kSpinAngle];
    spin.speed_rad_per_s = x[L::kSpinSpeed];
    spin.drive_integral_rad = x[L::kDriveIntegral];
  }
}

template <class L, class State>
void write_spin(const SpinState& spin, State& x) {
  if constexpr (L::kSpinSize > 0) {
    x[L::kSpinAngle] = spin.angle_rad;
    x[L::kSpinSpeed] = spin.speed_rad_per_s;
    x[L::kDriveIntegral] = spin.drive_integral_rad;
  }
}

// The modal block, if any, is not part of Kinematics (modal_of()).
template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
Kinematics kinematics_of(const typename FreeLayout<kStatorDof, kMotor, Rotor>::State& x) {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  Kinematics k;
  k.rotor_pos = x.template segment<2>(L::kRotorPos);
  k.rotor_vel = x.template segment<2>(L::kRotorVel);
  if constexpr (kStatorDof == 2) {
    k.stator_pos = x.template segment<2>(L::kStatorPos);
    k.stator_vel = x.template segment<2>(L::kStatorVel);
  }
  read_spin<L>(x, k.spin);
  return k;
}

// x sized already (sized_state() for a flexible rotor).
template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
void store_kinematics(const Kinematics& k, typename FreeLayout<kStatorDof, kMotor, Rotor>::State& x) {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  x.template segment<2>(L::kRotorPos) = k.rotor_pos;
  x.template segment<2>(L::kRotorVel) = k.rotor_vel;
  if constexpr (kStatorDof == 2) {
    x.template segment<2>(L::kStatorPos) = k.stator_pos;
    x.template segment<2>(L::kStatorVel) = k.stator_vel;
  }
  write_spin<L>(k.spin, x);
}

}  // namespace rotor_rub::core
