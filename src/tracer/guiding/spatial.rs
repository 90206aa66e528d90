//! **Where in the scene a bounce is**: the spatial half of Müller et al.'s SD-tree, a binary
//! tree over the scene's box, each node cut in two at its middle across the axes in turn (x,
//! y, z, x, …). Its leaves are *cells*; cells are cut where many bounces were recorded, so the
//! guide is fine where paths go and coarse where they seldom do. Within a cell, bounces are
//! told apart by which way their surface faces ([`facing`]): each cell has a directional
//! distribution (`quadtree.rs`) per facing, so that the floor and a wall in one cell, which see
//! light from different half-spheres, do not share one (a shared one sent a quarter to a half
//! of the guide's draws at cornell's floor below it, where no light arrives).
//!
//! Invariants: node 0 is the root; a split node's two children are adjacent (`children`, then
//! `children + 1`: the lower half, then the upper); cells are numbered from 0 in the order
//! [`SpatialTree::refined`] makes them, which depends only on the tree and the counts, never
//! on threads. A point outside the box belongs to the cell nearest it along each axis's cuts.

use crate::tracer::math::aabb::Aabb;
use crate::tracer::math::real::Vec3;

/// The ways a bounce's surface may face: the six directions of the axes (the normal's largest
/// component and its sign), and none, in a medium.
pub const FACINGS: usize = 7;

/// Which way the surface of a bounce faces: `0..6` for +x, −x, +y, −y, +z, −z, by the largest
/// component of its unit `normal` (the side the path arrived on); 6 without one (a
/// scattering in a medium).
///
/// ```
/// use raypool::tracer::guiding::spatial::facing;
/// use raypool::tracer::math::real::Vec3;
/// assert_eq!(facing(Some(Vec3::new(0.1, -0.9, 0.3))), 3);
/// assert_eq!(facing(None), 6);
/// ```
#[inline]
pub fn facing(normal: Option<Vec3>) -> usize {
    let Some(n) = normal else { return 6 };
    let a = n.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * axis + usize::from(n[axis] < 0.0)
}

/// The deepest the tree cuts: 2⁻¹⁰ of the box's side along each axis.
const MAX_DEPTH: u32 = 30;

/// A node: a cell, or a cut in two.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Node {
    /// A leaf: cell number `0`.
    Cell(u32),
    /// Cut at the middle; the lower half is node `children`, the upper `children + 1`.
    Split { children: u32 },
}

/// The binary tree over the scene's box.
#[derive(Clone, Debug, PartialEq)]
pub struct SpatialTree {
    bounds: Aabb,
    nodes: Vec<Node>,
}

impl SpatialTree {
    /// One cell over `bounds`.
    pub fn new(bounds: Aabb) -> SpatialTree {
        SpatialTree { bounds, nodes: vec![Node::Cell(0)] }
    }

    /// How many cells.
    pub fn cells(&self) -> usize {
        self.nodes.iter().filter(|n| matches!(n, Node::Cell(_))).count()
    }

    /// The cell holding `p`.
    #[inline]
    pub fn cell(&self, p: Vec3) -> usize {
        let (mut low, mut high) = (self.bounds.min, self.bounds.max);
        let (mut node, mut axis) = (0usize, 0usize);
        loop {
            match self.nodes[node] {
                Node::Cell(cell) => return cell as usize,
                Node::Split { children } => {
                    let middle = 0.5 * (low[axis] + high[axis]);
                    if p[axis] < middle {
                        (node, high[axis]) = (children as usize, middle);
                    } else {
                        (node, low[axis]) = (children as usize + 1, middle);
                    }
                    axis = (axis + 1) % 3;
                }
            }
        }
    }

    /// The tree the next pass learns into: every cell that recorded more than `threshold`
    /// bounces (`counts`, per cell) is cut in two, and its halves again while half its count
    /// (as if spread evenly) is still above it (Müller et al.'s rule, `threshold` their
    /// `c·√(2ᵏ)`). Returns the new tree and, per new cell, the cell of this tree it lies in,
    /// whose directions it starts from.
    pub fn refined(&self, counts: &[u64], threshold: f64) -> (SpatialTree, Vec<usize>) {
        let mut nodes = vec![Node::Cell(0)];
        let mut origins = Vec::new();
        // (old node, new node, the bounces assumed in it (None: copy the old node), depth).
        let mut stack = vec![(0usize, 0usize, None::<f64>, 0u32)];
        while let Some((old, new, assumed, depth)) = stack.pop() {
            let (count, origin) = match (self.nodes[old], assumed) {
                (Node::Split { children }, None) => {
                    let first = nodes.len();
                    nodes[new] = Node::Split { children: first as u32 };
                    nodes.extend([Node::Cell(0); 2]);
                    // Upper half pushed first, so the lower half is numbered first.
                    stack.push((children as usize + 1, first + 1, None, depth + 1));
                    stack.push((children as usize, first, None, depth + 1));
                    continue;
                }
                (Node::Cell(cell), None) => (counts[cell as usize] as f64, cell as usize),
                (Node::Cell(cell), Some(count)) => (count, cell as usize),
                (Node::Split { .. }, Some(_)) => unreachable!("only cells are cut further"),
            };
            if count > threshold && depth < MAX_DEPTH {
                let first = nodes.len();
                nodes[new] = Node::Split { children: first as u32 };
                nodes.extend([Node::Cell(0); 2]);
                stack.push((old, first + 1, Some(count / 2.0), depth + 1));
                stack.push((old, first, Some(count / 2.0), depth + 1));
            } else {
                nodes[new] = Node::Cell(origins.len() as u32);
                origins.push(origin);
            }
        }
        (SpatialTree { bounds: self.bounds, nodes }, origins)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tracer::math::real::Real;

    #[test]
    fn a_busy_cell_is_cut_until_its_halves_are_quiet() {
        let tree = SpatialTree::new(Aabb { min: Vec3::ZERO, max: Vec3::splat(8.0) });
        // 100 bounces against a threshold of 30: halves of 50, quarters of 25.
        let (cut, origins) = tree.refined(&[100], 30.0);
        assert_eq!((cut.cells(), origins), (4, vec![0; 4]));
        // Cut in x, then y: the four cells in order (x low, y low), (x low, y high), ….
        let cells: [[Real; 3]; 4] = [[1.0, 1.0, 1.0], [1.0, 7.0, 1.0], [7.0, 1.0, 1.0], [7.0, 7.0, 7.0]];
        assert_eq!(cells.map(|p| cut.cell(Vec3::from_array(p))), [0, 1, 2, 3]);
        // Only the second cell is busy next time.
        let (again, origins) = cut.refined(&[0, 100, 0, 0], 60.0);
        assert_eq!((again.cells(), origins), (5, vec![0, 1, 1, 2, 3]));
    }
}
