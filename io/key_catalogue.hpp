#pragma once
/// \file
/// An opt-in record of the keys each table of a file accepts, filled by the table readers
/// (io/toml_reader.hpp, TableReader::reject_unknown) while a KeyCatalogue is alive on the
/// thread. It lets a test check that scenarios/reference.toml lists every key the reader
/// accepts; without one, nothing is recorded.

#include <string>
#include <vector>

namespace cleave::io {

/// One table as a reader saw it: the file, the table's name as errors write it ("wall[2]",
/// "contact.particle_wall") and the keys it accepts. Absent optional tables are recorded too.
struct AcceptedKeys {
  std::string source;
  std::string table;
  std::vector<std::string> keys;
};

/// Records every table read on this thread while it is alive (one at a time).
class KeyCatalogue {
 public:
  KeyCatalogue() : previous_(current()) { current() = this; }
  ~KeyCatalogue() { current() = previous_; }
  KeyCatalogue(const KeyCatalogue&) = delete;
  KeyCatalogue& operator=(const KeyCatalogue&) = delete;

  [[nodiscard]] const std::vector<AcceptedKeys>& tables() const { return tables_; }

  /// The catalogue readers record into; null when none is alive.
  static KeyCatalogue*& current() {
    thread_local KeyCatalogue* catalogue = nullptr;
    return catalogue;
  }
  void record(AcceptedKeys table) { tables_.push_back(std::move(table)); }

 private:
  KeyCatalogue* previous_;
  std::vector<AcceptedKeys> tables_;
};

}  // namespace cleave::io
