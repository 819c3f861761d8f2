//! The spatial half of the guide: a binary tree over a box of world space whose leaves are
//! split in half, across their longest side, where training records crowd (Müller et al.
//! 2017 split by record count the same way, cycling the axes). Leaf indices stay dense: a
//! split leaf keeps its index for its lower half and the upper half gets the next free one.

use glam::Vec3;

/// One node: an inner node's split plane and children, or a leaf's index.
#[derive(Clone, Copy, Debug)]
enum Node {
    Inner {
        axis: u8,
        split: f32,
        /// Node indices of the lower and upper halves.
        children: [u32; 2],
    },
    Leaf(u32),
}

/// A binary space partition of a box, refined leaf by leaf.
#[derive(Clone, Debug)]
pub struct SpatialTree {
    nodes: Vec<Node>,
    /// Per leaf: its node and its box.
    leaves: Vec<(u32, Vec3, Vec3)>,
}

impl SpatialTree {
    /// One leaf over the box `lo..hi`.
    pub fn new(lo: Vec3, hi: Vec3) -> Self {
        Self {
            nodes: vec![Node::Leaf(0)],
            leaves: vec![(0, lo, hi)],
        }
    }

    /// Number of leaves.
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// The leaf holding `p`; a point outside the root box goes to the leaf nearest it along
    /// each split.
    #[inline]
    pub fn leaf_of(&self, p: Vec3) -> usize {
        let mut node = 0usize;
        // Depth is bounded by the node count; the loop ends at a leaf.
        loop {
            match self.nodes.get(node) {
                Some(Node::Inner {
                    axis,
                    split,
                    children,
                }) => {
                    let upper = p[*axis as usize] >= *split;
                    node = children[usize::from(upper)] as usize;
                }
                Some(Node::Leaf(leaf)) => return *leaf as usize,
                None => return 0,
            }
        }
    }

    /// Splits leaf `leaf` in half across its box's longest side. Returns the index of the new
    /// (upper) leaf, or `None` when the box is too thin to split or `leaf` does not exist.
    pub fn split(&mut self, leaf: usize) -> Option<usize> {
        let &(node, lo, hi) = self.leaves.get(leaf)?;
        let extent = hi - lo;
        let axis = extent.max_position();
        let split = 0.5 * (lo[axis] + hi[axis]);
        if !(split > lo[axis] && split < hi[axis]) {
            return None;
        }
        let upper_leaf = self.leaves.len();
        let (first, upper_leaf_u32) = (
            u32::try_from(self.nodes.len()).ok()?,
            u32::try_from(upper_leaf).ok()?,
        );
        let mut mid_hi = hi;
        mid_hi[axis] = split;
        let mut mid_lo = lo;
        mid_lo[axis] = split;
        self.nodes.push(Node::Leaf(leaf as u32));
        self.nodes.push(Node::Leaf(upper_leaf_u32));
        self.nodes[node as usize] = Node::Inner {
            axis: axis as u8,
            split,
            children: [first, first + 1],
        };
        self.leaves[leaf] = (first, lo, mid_hi);
        self.leaves.push((first + 1, mid_lo, hi));
        Some(upper_leaf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_halve_the_longest_side_and_points_find_their_leaf() {
        let mut tree = SpatialTree::new(Vec3::ZERO, Vec3::new(4.0, 1.0, 1.0));
        assert_eq!(tree.split(0), Some(1));
        assert_eq!(tree.leaf_of(Vec3::new(1.0, 0.5, 0.5)), 0);
        assert_eq!(tree.leaf_of(Vec3::new(3.0, 0.5, 0.5)), 1);
        assert_eq!(tree.split(1), Some(2));
        assert_eq!(tree.leaf_of(Vec3::new(3.5, 0.5, 0.5)), 2);
        assert_eq!(tree.leaf_of(Vec3::new(2.5, 0.5, 0.5)), 1);
        // Outside the root box: the nearest leaf.
        assert_eq!(tree.leaf_of(Vec3::new(9.0, 0.5, 0.5)), 2);
        assert_eq!(tree.leaf_of(Vec3::new(-9.0, 0.5, 0.5)), 0);
        assert_eq!(tree.leaf_count(), 3);
        assert_eq!(tree.split(7), None);
    }
}
