#pragma once
// Arm models from URDF (read with urdfdom). The chain from the root link through the moving
// joints (revolute, continuous, prismatic) becomes the model's joints under the Urdf convention;
// links joined by fixed joints ride on the body before them. Bodies are named by link: body 0 the
// root link, body k the child link of moving joint k, body n + 1 the one link fixed to the last
// moving link (a tool flange, `ee_link`), else "flange" with no geometry.
//
// Collision geometry as capsules, each bounding its shape (never smaller):
//   sphere r                -> a capsule with both ends at the centre, radius r (exact)
//   cylinder r, length l    -> segment = the cylinder's axis (l), radius r: exact along the
//                              side, a hemispherical cap of r past each flat end
//   box half extents h      -> segment along the longest axis (+-h_max), radius = the hypotenuse
//                              of the other two half extents (the box's corners on the surface)
//   mesh                    -> refused, naming the link and the file
// A continuous joint has no limits (+-infinity).
#include <string>

#include <starm/arm.hpp>

namespace st::arm {

// Throws InputError "FILE: what is wrong" (missing file, malformed XML, a joint whose parent link
// is unknown, a branch with moving joints on two sides, a non-finite number, a mesh).
ArmModel loadUrdf(const std::string& path, const std::string& name = "");
// The same from text; `file` names it in errors.
ArmModel parseUrdf(const std::string& xml, const std::string& file, const std::string& name = "");

// An SRDF's <disable_collisions link1="A" link2="B"/> as allowed pairs of m (links by their URDF
// names; pairs of links on one body are already never tested). Other SRDF elements are ignored.
// Throws InputError "FILE: what" (missing file, malformed XML, a link the robot has not).
void applySrdf(ArmModel& m, const std::string& path);
void applySrdfText(ArmModel& m, const std::string& xml, const std::string& file);

}  // namespace st::arm
