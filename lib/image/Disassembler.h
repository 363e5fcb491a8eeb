//! @file Disassembler.h
//! @brief Human-readable views of an image: the listing of `isocc --disasm` and the annotated
//!        hex dump of `isocc --dump=hex`. Both are safe on unverified images (operands out of
//!        range print as `?`, undecodable bytes as `.byte`), so they also serve to inspect bad
//!        images.
#pragma once

#include <string>
#include <vector>

#include "image/Image.h"
#include "image/Opcode.h"

namespace iso::image {

/// The operands of one decoded instruction with names: constants' values, R numbers, system
/// variables with their axis, procedure names, labels `L0012` for code offsets.
std::string formatOperands(const Image& img, const Instr& in);

/// The full listing: a summary of the tables, then per procedure a header (index, kind, name,
/// file, code range) and one line per instruction (offset, mnemonic, operands), labels before
/// jump targets and the source `file:line` (and N number) of each statement.
std::string disassemble(const Image& img);

/// Every byte of the encoded image with what it means, one field per line:
/// `0018: 01 00  # section 0 id 1 (strings)`. `#` starts a comment; the format is read back
/// by the golden-test fixture converter (tests/golden/images/).
std::string hexDump(const Image& img);

} // namespace iso::image
