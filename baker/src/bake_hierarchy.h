// The hierarchical solver's quadtrees and links in the bake's integer form
// (relight::BakeHierarchy; sections HIER and LINK of docs/bake-format.md),
// so run-time emitters can re-solve radiosity from the bake alone.
#pragma once

#include <vector>

#include "hierarchy.h"
#include "hierarchy_links.h"
#include "mesher.h"
#include "relight/bake/bake.h"

namespace relight::baker {

// Node areas to Q32.32 m^2 (inner nodes the exact sum of their children's),
// factors to UQ0.32, gradients to Q8.23 per metre. A factor that rounds to 0
// drops its gradient (the solver skips that direction), and a link whose two
// factors round to 0 is left out. Throws std::runtime_error if a value does
// not fit its format.
BakeHierarchy MakeBakeHierarchy(const Mesh& mesh, const Hierarchy& h,
                                const std::vector<HierarchyLink>& links);

}  // namespace relight::baker
