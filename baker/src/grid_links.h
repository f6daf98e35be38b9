// Links from the hierarchy's nodes to the calculation grids' points (section
// GLNK, docs/hierarchy.md "Grids"), so light sources placed on surfaces at
// run time light the grids: a point's irradiance is sum f B over its links.
//
// The factors come from the dense gather the grids' bases use already
// (BakerCore::gather: point-to-patch factors with visibility), summed over
// a node's leaves, so a node's factor is exact. The level is chosen as BF
// refinement does, top-down from each surface's root: a node is linked
// when the gather over its leaves differs from the node's factor spread
// evenly over its area by at most epsilon in total (sum_j |G_j - F a_j / A|),
// i.e. when treating its exitance as uniform can err by at most epsilon x
// the node's exitance range; else its children are tried. Far nodes are
// seen evenly and stay coarse, near ones split down to the leaves.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "hierarchy.h"
#include "mesher.h"
#include "relight/bake/bake.h"

namespace relight::baker {

// Fills out->grid_link_* for the grids' points in order (gather: per grid,
// points x patches). Throws std::runtime_error if the links exceed the
// format's limits.
void MakeGridLinks(const Mesh& mesh, const Hierarchy& h, const std::vector<Eigen::MatrixXd>& gather,
                   double epsilon, BakeHierarchy* out);

}  // namespace relight::baker
