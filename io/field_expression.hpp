#pragma once
// A scalar field f(x, y, z, t) written as a formula in a scenario file, e.g. a stage's
// prescribed temperature "1773 - 2e9*t + 4e3*x". Parsed and evaluated by muparser
// (Debian's libmuparser-dev), which is kept in field_expression.cpp.

#include <memory>
#include <string>

namespace cleave::io {

class FieldExpression {
 public:
  /// Parses `text` in the variables x, y, z and t; throws std::invalid_argument with
  /// muparser's message and the character position for a formula it cannot read (a syntax
  /// error, an unknown name or function).
  explicit FieldExpression(const std::string& text);
  ~FieldExpression();
  FieldExpression(FieldExpression&&) noexcept;
  FieldExpression& operator=(FieldExpression&&) noexcept;
  FieldExpression(const FieldExpression&) = delete;
  FieldExpression& operator=(const FieldExpression&) = delete;

  /// The formula's value at (x, y, z, t). Not thread-safe (one evaluator per thread).
  double operator()(double x, double y, double z, double t) const;
  const std::string& text() const { return text_; }

 private:
  struct Impl;
  std::string text_;
  std::unique_ptr<Impl> impl_;
};

/// `text` with every variable x, y, z (a whole name, not part of another) replaced by
/// "(x/u)" for u = `metres_per_unit`: the same formula of the coordinates in metres. The text
/// itself when u is 1.
std::string lengths_in_metres(const std::string& text, double metres_per_unit);

}  // namespace cleave::io
