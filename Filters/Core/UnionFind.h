// StrataMesh core: the root of an element in a union-find forest (regions' pieces, the
// classification's components). No VTK.
#ifndef StrataMeshCore_UnionFind_h
#define StrataMeshCore_UnionFind_h

namespace strata
{

/// The root of k in a union-find forest of parent links (parent[r] == r at a root), halving
/// the paths on the way. `Parents`: any random-access container of int.
template<class Parents>
int rootOf(Parents& parent, int k)
{
  while (parent[k] != k)
  {
    parent[k] = parent[parent[k]];
    k = parent[k];
  }
  return k;
}

} // namespace strata

#endif
