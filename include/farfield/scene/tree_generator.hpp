// An L-system tree: the kind of test scene paper 002 used (Sec. 5, Table 1: trees and a
// topiary of thousands of branches and leaves, after Prusinkiewicz et al.), and the model that
// `generate field` copies for its scaling experiment (Sec. 6.3, App. B).
//
// The axiom is rewritten `iterations` times by the rules (a bracketed 0L-system, Prusinkiewicz
// and Lindenmayer, "The Algorithmic Beauty of Plants", ch. 1), then read by a 3D turtle:
//   F      a branch segment: a tapered cylinder of the current length and radius; the radius
//          shrinks by segment_taper along it
//   + -    turn left / right by branch_angle_deg (about the turtle's up)
//   & ^    pitch down / up by branch_angle_deg (about the turtle's left)
//   / \    roll by +/- divergence_deg (about the heading)
//   |      turn around
//   [ ]    start / end a branch: one level deeper, length x length_ratio, radius x radius_ratio
//   L      a cluster of `leaves` leaves along the last segment
//   other letters: variables that only the rules read
// Each angle and segment length varies by up to +/- jitter (a fraction) from `seed`, and
// segments bend a little towards the ground (tropism, ABOP Sec. 2.2), so a seed is one tree.
//
// The default rules are the ternary tree of ABOP Fig. 2.8 (with 'L' erased each step, so only
// the last twigs keep their leaves): at the default 6 iterations, 1457 branch segments of
// 8 sides and 729 clusters of 10 leaves, about 52K triangles; a field of 256 has 13M. Each
// iteration triples both.
//
// Geometry: +Y up, the base of the trunk at the origin (or `base`), the top of the branches
// at `height`; leaves reach up to leaf_size higher. Leaves are double-sided: two quads with
// opposite normals, so they show from both sides under back-face culling. Colours are in the
// vertices (bark brown, leaves green, both with jitter); the material is opaque white.
//
// Objects (kind tree), so that spatial techniques have parts to cull: NAME/trunk holds every
// branch above `split_depth`, each branch that starts at that depth is NAME/subtree_K with its
// twigs and leaves. split_depth is the shallowest bracket depth holding at least `objects - 1`
// branches (the deepest one if none does); objects = 1 keeps the whole tree as one object,
// NAME. The default tree is "tree", in 28 objects.
//
// Deterministic: the same options give the same scene, byte for byte.
//
// Cost: the default tree takes about 10 ms on one core.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "farfield/core/progress.hpp"
#include "farfield/core/result.hpp"
#include "farfield/scene/scene.hpp"

namespace farfield {

struct TreeOptions {
  std::string axiom = "FA";
  // "X=successor": each X of the string becomes the successor at every iteration; a letter
  // without a rule stays as it is.
  std::vector<std::string> rules = {"A=F[&FLA]/[&FLA]/[&FLA]", "L="};
  uint32_t iterations = 6;         // rewriting steps, 0 to 12
  double branch_angle_deg = 30.0;  // turn of + - & ^, degrees
  double divergence_deg = 120.0;   // roll of / \, degrees
  double length_ratio = 0.78;      // segment length of a branch / of its parent
  double radius_ratio = 0.8;       // radius of a branch at its base / its parent's radius there
  double segment_taper = 0.9;      // radius at the end of a segment / at its start
  double jitter = 0.2;             // random variation of angles and lengths, fraction
  double height = 10.0;            // top of the branches above the base, metres
  double leaf_size = 0.3;          // length of a leaf, metres
  uint32_t leaves = 10;            // leaves per 'L'; 0: a bare tree
  uint32_t sides = 8;              // sides of a branch cylinder, 3 to 64
  uint32_t objects = 28;           // about this many objects (see above); 1: one object
  uint64_t seed = 1;
};

// Checks the options, rules and axiom included; the message names the option as on the
// command line.
Result<void> validate_tree_options(const TreeOptions& options);

// Appends one tree standing at `base` to the builder's scene (no object may be open), its
// objects named after `name` as above. Fails on bad options, or when the tree would have over
// 50M triangles. Progress, when given, advances once per object.
Result<void> add_tree(SceneBuilder& builder, const TreeOptions& options, const glm::vec3& base,
                      std::string_view name, Progress* progress = nullptr);

// One tree in a new scene, its base at the origin.
Result<Scene> generate_tree(const TreeOptions& options, Progress& progress);

}  // namespace farfield
