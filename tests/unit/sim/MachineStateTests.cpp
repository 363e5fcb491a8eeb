//! @file MachineStateTests.cpp
//! @brief The machine state beside the axes: R with its read-ahead journal, I/O, the input
//!        schedule and PLC sequences.
#include <string>

#include <doctest/doctest.h>

#include "image/Opcode.h"
#include "sim/FaultOf.h"
#include "sim/MachineState.h"
#include "sim/RunMath.h"

using namespace iso::sim;
using iso::image::SysVarId;

namespace {

constexpr auto kIn = static_cast<uint8_t>(SysVarId::AaIn);
constexpr auto kOut = static_cast<uint8_t>(SysVarId::AaOut);

iso::machine::Machine machine() {
  iso::machine::Machine m;
  m.numInputs = 4;
  m.numOutputs = 2;
  m.rPreset[7] = 1.5;
  m.inputs[2] = {{0.5, 1}, {1.0, 0}};
  m.inputs[1] = {{0.5, 1}};
  return m;
}

std::string faultOf(MachineState& ms, uint8_t sv, double index, double value) {
  return iso::sim::test::faultOf([&] { ms.ioWrite(sv, index, value); });
}

} // namespace

TEST_CASE("machine state: R presets and the read-ahead journal") {
  MachineState ms;
  ms.start(machine());
  CHECK(ms.r(7) == 1.5);
  ms.setR(1, 10, false);
  const size_t mark = ms.markR();
  ms.setR(1, 20, true);
  ms.setR(1, 30, true); // one journal entry per R and statement
  ms.markR();
  ms.setR(7, 2, true);
  ms.rollbackR(mark);
  CHECK(ms.r(1) == 10);
  CHECK(ms.r(7) == 1.5);
  ms.setR(2, 5, true);
  ms.commitR();
  ms.rollbackR(0);
  CHECK(ms.r(2) == 5);
}

TEST_CASE("machine state: inputs, outputs and their faults") {
  MachineState ms;
  ms.start(machine());
  CHECK(ms.setInput(3, 1));
  CHECK_FALSE(ms.setInput(3, 1)); // no change
  CHECK_FALSE(ms.setInput(9, 1)); // not an input
  CHECK(ms.ioRead(kIn, 3) == 1);
  const IoWrite w = ms.ioWrite(kOut, 1, 1);
  CHECK(w.output);
  CHECK(w.index == 1);
  CHECK(ms.ioRead(kOut, 1) == 1);
  CHECK(faultOf(ms, kOut, 1, 0.5) == "$aa_out[1] = 0.5: only 0 or 1 can be written");
  CHECK(faultOf(ms, kOut, 2, 1) == "$aa_out index 2 is outside 0..1");
}

TEST_CASE("machine state: the input schedule in time, then index order") {
  MachineState ms;
  ms.start(machine());
  CHECK(ms.nextInputTime() == 0.5);
  InputStep s;
  REQUIRE(ms.takeInputStep(0.5, s));
  CHECK(s.index == 1);
  REQUIRE(ms.takeInputStep(0.5, s));
  CHECK(s.index == 2);
  CHECK_FALSE(ms.takeInputStep(0.5, s));
  CHECK(ms.nextInputTime() == 1.0);
}

TEST_CASE("machine state: PLC sequences end in time, then start order") {
  MachineState ms;
  ms.start(machine());
  ms.startSeq(8, 2.0, nullptr);
  ms.startSeq(3, 1.0, nullptr);
  ms.startSeq(4, 1.0, nullptr);
  RunningSeq s;
  CHECK_FALSE(ms.takeEndedSeq(0.5, s));
  REQUIRE(ms.takeEndedSeq(1.0, s));
  CHECK(s.m == 3);
  REQUIRE(ms.takeEndedSeq(1.0, s));
  CHECK(s.m == 4);
  CHECK(ms.seqs().size() == 1);
  ms.stopSeqs();
  CHECK(ms.seqs().empty());
}
