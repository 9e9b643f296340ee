// What the clusters technique draws in a frame, chosen over the cluster hierarchy (paper 001,
// Sec. 4.5) without GL, so that tests can check it on hand-made hierarchies. A node's
// representations, coarsest first: its textured box (box_set.hpp), its cluster mesh (skipped
// where the box's error is no larger), then its objects and children; an object's: its box,
// its levels of detail (those of no less error than the box skipped), the object whole.
//  - by error (no budget): from the root down, a node's box or cluster wherever its error
//    projects below `error_px` pixels, else its objects (each as the coarsest
//    representation under that error, or whole) and its children;
//  - under a budget of triangles (the frame-time budget through the cost model, each draw
//    counted as the triangles it costs as much as): the paper's
//    best-first refinement (Sec. 4.5.2): a complete coarsest representation of what the
//    frustum sees first (the root's box or cluster), then the representation whose error
//    covers the most pixels refined (a box into its cluster, a cluster into its objects and
//    children, an object one level finer) while the triangles stay within the budget, so
//    that every step is complete.
// Two traversals: `refined` (the default) visits only the nodes it refines and their children,
// from bounds stored per node; `paper` first classifies every node and object of the scene
// (Sec. 4.5.1's first pass over all objects, O(n), which Sec. 6 names the method's limit),
// then refines from what that pass found, so that both can be measured.
// Temporal coherence under a budget (Sec. 4.6), so that a node on the budget's edge does not
// flip every frame: the paper's rule (the technique's default) refines a cluster drawn in
// the last frame into its children only once the walk has wanted to for more than
// `hysteresis` frames in a row; the `flips` rule delays only a cluster that went back from
// its children within the last `hysteresis` frames. The switch back is at once in both, as
// the paper's.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "farfield/core/frustum.hpp"
#include "farfield/scene/scene.hpp"
#include "farfield/spatial/occlusion_map.hpp"
#include "farfield/techniques/clusters/accuracy_table.hpp"
#include "farfield/techniques/clusters/box_set.hpp"
#include "farfield/techniques/clusters/cluster_tree.hpp"
#include "farfield/techniques/clusters/lod_set.hpp"

namespace farfield {

enum class ClusterTraversal { refined, paper };

// Paper 001, Sec. 3.1: an object's benefit, a weighted average of its image-space size, its
// nearness to the line of sight (focus), its slowness across the screen and its kind's
// weight (semantics; a cluster's: the largest of its objects', Sec. 4.5.1), each in [0, 1].
// Under a budget the refinement order is the projected error times the benefit; all weights
// 0 (the default): the projected error alone.
struct BenefitWeights {
  float size = 0, focus = 0, speed = 0, semantics = 0;
  bool any() const { return size + focus + speed + semantics > 0; }
};
// The semantic weight of a kind of object: buildings and unclassified meshes 1, trees and
// fountains 0.8, terrain 0.7, parks, streets, curbs and ground 0.5.
float semantic_weight(ObjectKind kind);
enum class HysteresisRule { flips, paper };

struct SelectionView {
  const Frustum* frustum = nullptr;
  glm::vec3 eye{0.0f};
  float pixel = 1e-3f;  // the size of a pixel at unit distance (view centre), metres per metre
  std::optional<Bounds3> near_box;  // drawing for a near region only: what meets it
  float error_px = 1.0f;            // by error: the largest projected error
  double max_triangles = -1.0;      // >= 0: under this budget instead
  // What a draw costs, counted in triangles, under a budget. Boxes are charged none: the
  // chosen boxes of an atlas page are one multi-draw, gathered into one draw beyond 64.
  double triangles_per_draw = 0.0;
  int hysteresis = 0;  // under a budget: frames a refinement waits (0: none)
  HysteresisRule hysteresis_rule = HysteresisRule::paper;
  const OcclusionMap* occlusion = nullptr;  // what it hides is not drawn, if given
  // Errors from the accuracy tables (image errors, by the direction each node and object is
  // seen from), if given; else the geometric errors.
  const AccuracyTable* accuracy = nullptr;
  // > 0: the tables' finest comparison put this many texels across a subject's bounds; an
  // image error below that texel (a representation that passed there) is extrapolated, and
  // the geometric error decides instead. 0: the tables' errors at every scale.
  float accuracy_finest_px = 0.0f;
  // Under a budget, with any weight: the benefit's factors.
  BenefitWeights benefit;
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  // the line of sight, unit
  float half_fov_rad = 0.785f;           // from the line of sight to a corner of the view
  glm::vec3 velocity{0.0f};              // of the eye since the last frame, metres
  float width_px = 1024.0f;
  // A box chosen whose bounds' diagonal projects below this many pixels is drawn as its
  // average-colour box (paper 001, Sec. 4.2: "less than a few pixels"; its error: that
  // diagonal), by error only where that is within error_px too. 0: never.
  float average_px = 0.0f;
};

// One thing to draw: a cluster's mesh, an object's level of detail, an object whole, or a
// textured box (an object's or a cluster's) or its average-colour box (average_boxes.hpp).
struct Choice {
  enum class Kind : uint8_t { cluster, lod, whole, box, average };
  Kind kind;
  uint32_t index;  // node, into LodSet::lods, object, or into BoxSet::boxes (box and average)
};

struct SelectionStats {
  uint64_t nodes_visited = 0;  // nodes whose visibility was tested
  uint64_t triangles = 0;      // of the choices
  float largest_error_px = 0;  // the coarsest choice's projected error
  // Nodes drawn as their cluster this frame and refined the last, or the other way round.
  uint64_t switches = 0;
  // Under a budget: the least budget that would have taken a refinement skipped for want of
  // it (at least that: an opening stops once it cannot fit); infinite where none was.
  double needed = INFINITY;
};

class ClusterSelection {
 public:
  // All outlive the selection; `boxes` may be null (no textured boxes); `averages`: every box
  // has an average-colour box.
  ClusterSelection(const Scene& scene, const ClusterTree& tree, const LodSet& lods,
                   const BoxSet* boxes = nullptr, bool averages = false);
  // This frame's choices (replacing `out`'s).
  SelectionStats select(const SelectionView& view, ClusterTraversal traversal,
                        std::vector<Choice>& out);
  // The nodes that the last select() drew as their cluster where the frame before drew their
  // children, or the other way round (`refined`): SelectionStats::switches of them.
  struct NodeSwitch {
    uint32_t node;
    bool refined;
  };
  const std::vector<NodeSwitch>& switched() const { return switched_; }

 private:
  static constexpr uint32_t kWhole = UINT32_MAX;
  static constexpr uint32_t kBox = UINT32_MAX - 1;
  // A representation in the budget's front: a node (slot == kNone) as its cluster (level
  // 0) or its box (kBox), or an object at a level (into LodSet::lods, kBox, or kWhole).
  static constexpr uint32_t kNone = UINT32_MAX;
  struct Item {
    uint32_t node, slot, level;  // slot: the object's, into slots_
    uint32_t direction;  // of the accuracy tables, towards the eye
    float distance;
    float benefit;  // SelectionView::benefit's average, 1 without weights
    uint64_t triangles;
    double cost;  // triangles and draws (SelectionView::triangles_per_draw)
    bool live;
    bool in_frustum;  // a node's bounds wholly inside the frustum
  };
  struct Seen {
    bool visible;
    bool clusterable;  // a cluster may stand for it (within the near region, if any)
    bool in_frustum;   // wholly inside the frustum: so is all it holds
    float distance;
    uint32_t direction;  // of the accuracy tables, towards the eye (0 without them)
  };
  // `in_frustum`: its parent's bounds lie wholly inside the frustum (no plane to test).
  Seen see(const Bounds3& box, bool in_frustum);
  Seen see_node(uint32_t node, bool in_frustum = false);
  Seen see_object(uint32_t slot, bool in_frustum = false);
  // A node to visit, and whether its parent lies wholly inside the frustum.
  struct Pending {
    uint32_t node;
    bool in_frustum;
  };
  void classify_all();
  float projected(float error_m, float distance) const;
  uint64_t object_triangles(uint32_t slot, uint32_t level) const;
  // Errors, metres: an object's at a level (0 for kWhole), a node's cluster mesh (level 0)
  // or box (kBox), seen from an accuracy-table direction.
  float object_error(uint32_t slot, uint32_t level, uint32_t direction) const;
  float node_error(uint32_t node, uint32_t level, uint32_t direction) const;
  uint32_t direction_of(const Bounds3& box) const;
  // The table's error, or the geometric one where the table's is below its finest texel for
  // a subject of diagonal `diagonal_m` (SelectionView::accuracy_finest_px).
  float resolved(float image_m, float geometric_m, float diagonal_m) const;
  float benefit_of(const Bounds3& box, float distance, float semantics) const;
  uint32_t node_box(uint32_t node) const { return node_slots_[node].box; }
  // Box `box` as drawn, the average-colour box where its subject (of diagonal `diagonal_m` at
  // `distance`) projects below `limit_px`; `error_px` becomes that projection then.
  Choice box_choice(uint32_t box, float diagonal_m, float distance, float limit_px,
                    float& error_px) const;
  void by_error(std::vector<Choice>& out, SelectionStats& stats);
  void under_budget(std::vector<Choice>& out, SelectionStats& stats);
  // The coarsest complete representation of a node's visible content, appended to `into`;
  // `seen`: how the node was seen this frame, if it was (an item's node: not seen again).
  // Stops, returning what it found so far, once that costs more than `limit`.
  double open(uint32_t node, const Seen* seen, bool use_cluster, std::vector<Item>& into,
              double limit = INFINITY);

  const Scene& scene_;
  const ClusterTree& tree_;
  const LodSet& lods_;
  const BoxSet* boxes_;
  bool averages_;
  // What selection reads of an object, in the hierarchy's order (ClusterTree::objects), so
  // that a node's objects lie together in memory: a frame's visits, after drawing has
  // flushed the caches, read a few cache lines each instead of one an array.
  struct ObjectSlot {
    Bounds3 bounds;
    uint32_t object;
    uint32_t first_lod, lod_end;  // into LodSet::lods
    uint32_t box;                 // into BoxSet::boxes, or BoxSet::kNone
    uint32_t whole_triangles;
    float diagonal;   // of its bounds, metres
    float semantics;  // semantic_weight of its kind
    float box_error_m;
    uint32_t box_triangles;
  };
  struct NodeSlot {
    uint32_t box;
    float diagonal;
    float semantics;  // the largest semantic weight of its objects
    float box_error_m;
    uint32_t box_triangles;
  };
  std::vector<ObjectSlot> slots_;
  std::vector<NodeSlot> node_slots_;
  // A node's part in a frame, for temporal coherence.
  enum State : uint8_t { unseen = 0, as_cluster, held, refined };
  void set_state(uint32_t node, State state);
  uint64_t count_switches();

  const SelectionView* view_ = nullptr;
  bool precomputed_ = false;
  uint64_t visited_ = 0;
  std::vector<Seen> node_seen_, object_seen_;  // the paper traversal's first pass
  std::vector<Item> items_, opened_;
  // Key (projected error times benefit, never negative) in the high half, item in the low: the
  // order of (key, item) pairs as one integer compare (the pairs' compare of floats then items
  // took a third of the budget pass); a heap of four children a node (four_ary_heap.hpp).
  std::vector<uint64_t> heap_;
  std::vector<Pending> stack_;
  std::vector<uint8_t> state_, last_state_;       // State per node, this frame and the last
  std::vector<uint32_t> touched_, last_touched_;  // nodes whose state_ is set
  std::vector<uint16_t> wanted_;                  // frames in a row a refinement was held
  std::vector<uint64_t> coarsened_at_;  // the frame a node went back from its children, or 0
  std::vector<NodeSwitch> switched_;
  uint64_t frame_ = 0;
};

}  // namespace farfield
