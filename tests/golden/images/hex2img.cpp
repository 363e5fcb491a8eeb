//! @file hex2img.cpp
//! @brief Test helper: converts a commented hex fixture (the format of `isocc --dump=hex`) into
//!        image bytes. `#` starts a comment; an optional leading `XXXX:` offset is checked
//!        against the bytes read so far; every other token is two hex digits. The CRC field
//!        (bytes 0x14..0x17) is recomputed unless the file contains the line `#! keep-crc`.
//!        Usage: iso_hex2img IN.hex OUT.isob
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "image/ImageWriter.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: iso_hex2img IN.hex OUT.isob\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::cerr << argv[1] << ": cannot open\n";
    return 2;
  }
  std::vector<uint8_t> bytes;
  bool keepCrc = false;
  std::string line;
  for (unsigned lineNo = 1; std::getline(in, line); ++lineNo) {
    if (line.rfind("#! keep-crc", 0) == 0) keepCrc = true;
    std::string data = line.substr(0, line.find('#'));
    std::istringstream ss(data);
    std::string tok;
    bool first = true;
    while (ss >> tok) {
      if (first && tok.size() > 1 && tok.back() == ':') {
        unsigned long off = std::stoul(tok.substr(0, tok.size() - 1), nullptr, 16);
        if (off != bytes.size()) {
          std::cerr << argv[1] << ":" << lineNo << ": offset " << tok << " but " << bytes.size() << " bytes so far\n";
          return 2;
        }
        first = false;
        continue;
      }
      first = false;
      auto hex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
      if (tok.size() != 2 || !hex(tok[0]) || !hex(tok[1])) {
        std::cerr << argv[1] << ":" << lineNo << ": '" << tok << "' is not a hex byte\n";
        return 2;
      }
      bytes.push_back(static_cast<uint8_t>(std::stoul(tok, nullptr, 16)));
    }
  }
  if (!keepCrc) iso::image::fixCrc(bytes);
  std::ofstream out(argv[2], std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    std::cerr << argv[2] << ": cannot write\n";
    return 2;
  }
  return 0;
}
