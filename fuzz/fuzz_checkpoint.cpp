/// \file
/// libFuzzer target: the checkpoint reader, io::decode_checkpoint (what io::read_checkpoint
/// runs on a file's bytes). Each input is decoded twice: as given (header, length and
/// checksum checks), and with its last 64 bytes replaced by the SHA-256 of everything before
/// them, so that mutated payloads get past the checksum and reach the decoders (world
/// state, fracture book, exact shapes). Expected for bad input: io::CheckpointError;
/// anything else escaping, a crash, a sanitizer report or a hang is a bug.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/checkpoint.hpp"
#include "io/result_dir.hpp"

namespace {

void decode(std::string_view bytes) {
  try {
    cleave::io::Checkpoint ck = cleave::io::decode_checkpoint(bytes, "fuzz.checkpoint");
    (void)ck;
  } catch (const cleave::io::CheckpointError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  constexpr std::size_t kChecksum = 64;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  decode(bytes);
  if (bytes.size() > kChecksum) {
    const std::size_t end = bytes.size() - kChecksum;
    bytes.replace(end, kChecksum, cleave::io::sha256_hex(std::string_view(bytes).substr(0, end)));
    decode(bytes);
  }
  return 0;
}
