#include "field_expression.hpp"

#include <muParser.h>

#include <fmt/format.h>

#include <cctype>
#include <stdexcept>

namespace cleave::io {

struct FieldExpression::Impl {
  mu::Parser parser;
  double x = 0.0, y = 0.0, z = 0.0, t = 0.0;
};

FieldExpression::FieldExpression(const std::string& text) : text_(text), impl_(std::make_unique<Impl>()) {
  mu::Parser& p = impl_->parser;
  try {
    p.DefineVar("x", &impl_->x);
    p.DefineVar("y", &impl_->y);
    p.DefineVar("z", &impl_->z);
    p.DefineVar("t", &impl_->t);
    p.SetExpr(text);
    p.Eval();  // muparser reads the formula on its first evaluation: its errors surface here
  } catch (const mu::Parser::exception_type& e) {
    std::string message = e.GetMsg();
    if (!message.empty() && message.back() == '.') message.pop_back();
    throw std::invalid_argument(message + " (in \"" + text + "\"; the variables are x, y, z and t)");
  }
}

FieldExpression::~FieldExpression() = default;
FieldExpression::FieldExpression(FieldExpression&&) noexcept = default;
FieldExpression& FieldExpression::operator=(FieldExpression&&) noexcept = default;

double FieldExpression::operator()(double x, double y, double z, double t) const {
  impl_->x = x;
  impl_->y = y;
  impl_->z = z;
  impl_->t = t;
  return impl_->parser.Eval();
}

std::string lengths_in_metres(const std::string& text, double metres_per_unit) {
  if (metres_per_unit == 1.0) return text;
  auto name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; };
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    // A number (its exponent's letters are not names): digits, '.', and e/E with a sign.
    if (std::isdigit(static_cast<unsigned char>(c)) != 0 || (c == '.' && i + 1 < text.size() &&
                                                              std::isdigit(static_cast<unsigned char>(text[i + 1])) != 0)) {
      std::size_t j = i;
      while (j < text.size() && (name_char(text[j]) || text[j] == '.' ||
                                 ((text[j] == '+' || text[j] == '-') && (text[j - 1] == 'e' || text[j - 1] == 'E'))))
        ++j;
      out.append(text, i, j - i);
      i = j;
    } else if (name_char(c)) {
      std::size_t j = i;
      while (j < text.size() && name_char(text[j])) ++j;
      const std::string name = text.substr(i, j - i);
      if (name == "x" || name == "y" || name == "z") {
        out += fmt::format("({}/{})", name, metres_per_unit);
      } else {
        out += name;
      }
      i = j;
    } else {
      out += c;
      ++i;
    }
  }
  return out;
}

}  // namespace cleave::io
