#pragma once
/// \file
/// What a frame shows besides the bodies, as polygons for write_vtp: the rig's walls and the
/// crack network (broken bonds and the sections grains split along), so that ParaView shows
/// both without filters.

#include "io/vtk_output.hpp"

namespace cleave::physics {
class World;
class FractureBook;
}  // namespace cleave::physics

namespace cleave::io {

/// Every wall of `world` as a surface: a platen its rectangle; an infinite plane a rectangle
/// over the bodies' bounding box projected onto it, with a margin of a quarter of the box's
/// diagonal on each side; a cylinder a closed tube of `segments` sides with its two end caps.
/// Cell data: "wall_index" (the wall's index in World::walls(), as in walls.csv's columns),
/// "name" (a string), "kind" (0 plane, 1 platen, 2 cylinder), "origin", "normal" (a
/// cylinder's axis), "velocity" (m/s) and "reaction_force_N" (the bodies' force on it at
/// the last step, walls.csv's).
BodyFrame wall_frame(const physics::World& world, int segments = 32);

/// The crack network as surfaces, one polygon per crack face, in the bodies' current poses:
///  * every broken bond as a regular octagon centred on its bond point, normal to the bond,
///    of the bond's face area (Bond::transmission: the touching faces at bonding), so the
///    drawn area is the intergranular crack area reported for it;
///  * with a fracture book, every face of a fragment that lies on one of its grain's
///    cleavage planes (the section a split cut), drawn once: by the piece on the plane's
///    lower side (the face's outward normal along the plane's normal). A piece split again
///    carries part of the section: the faces partition each cut's section.
/// Cell data: "kind" (1 broken bond: intergranular; 2 split section: transgranular),
/// "mode" (a bond's failure mode 1 tension, 2 shear, 3 bending, 4 torsion; 5 for a split
/// section; ParaView colours by it), "broken_at_s" (a bond's break time; NaN for a
/// section), "opened_at_s" (the time the crack opened: the bond's break, the split's),
/// "area_m2" (the crack face's area: the bond's face area; the section face's exact area,
/// FractureBook::section_area), "grain_a", "grain_b" (a bond's grains; a section's grain
/// twice), "normal". The areas of a frame sum to the run's crack areas at its time.
BodyFrame crack_frame(const physics::World& world, const physics::FractureBook* book);

}  // namespace cleave::io
