#pragma once
/// \file
/// Internal: the CGAL representation behind ExactPolyhedron, ExactPlane and ExactScalar.
/// Include only from the geometry library's CGAL translation units.

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <memory>
#include <mutex>
#include <vector>

#include "geometry/exact_polyhedron.hpp"

namespace cleave::geometry {

using Kernel = CGAL::Epeck;
using FT = Kernel::FT;
using Point3 = Kernel::Point_3;
using Plane3 = Kernel::Plane_3;
using ExactFT = FT::ET;  ///< the underlying exact rational type

struct ExactScalar::Impl {
  FT value;
};

struct ExactPlane::Impl {
  Plane3 plane;
};

/// The mass properties of one shape, computed once (exact moments of cells with large
/// rational coordinates cost tens of milliseconds, and a run asks for them several times:
/// the time-step check, the rigid body, fragments.csv). A copy of the Impl starts empty, so
/// an Impl copied and then changed never reads its original's values.
class MassMemo {
 public:
  MassMemo() = default;
  MassMemo(const MassMemo&) : memo_(std::make_unique<Memo>()) {}
  MassMemo& operator=(const MassMemo&) {
    memo_ = std::make_unique<Memo>();
    return *this;
  }
  MassMemo(MassMemo&&) noexcept = default;
  MassMemo& operator=(MassMemo&&) noexcept = default;

  /// `compute()` on the first call (from any thread), its value after.
  template <class F>
  const MassProperties& get(F&& compute) const {
    std::call_once(memo_->once, [&] { memo_->value = compute(); });
    return memo_->value;
  }

 private:
  struct Memo {
    std::once_flag once;
    MassProperties value;
  };
  std::unique_ptr<Memo> memo_ = std::make_unique<Memo>();
};

struct ExactPolyhedron::Impl {
  std::vector<Point3> vertices;
  std::vector<std::vector<int>> faces;  ///< CCW seen from outside
  MassMemo mass;                        ///< mass_properties(), once
};

/// Friend access for the CGAL translation units.
struct ExactAccess {
  static const ExactPolyhedron::Impl& impl(const ExactPolyhedron& p) { return *p.impl_; }
  static const Plane3& plane(const ExactPlane& p) { return p.impl_->plane; }
  static const FT& value(const ExactScalar& s) { return s.impl_->value; }
  static ExactPlane make_plane(const Plane3& plane) {
    return ExactPlane(std::make_shared<const ExactPlane::Impl>(ExactPlane::Impl{plane}));
  }
  static ExactPolyhedron make_polyhedron(ExactPolyhedron::Impl impl) {
    return ExactPolyhedron(std::make_shared<const ExactPolyhedron::Impl>(std::move(impl)));
  }
  static ExactScalar make_scalar(FT v) {
    return ExactScalar(std::make_shared<const ExactScalar::Impl>(ExactScalar::Impl{std::move(v)}));
  }
};

}  // namespace cleave::geometry
