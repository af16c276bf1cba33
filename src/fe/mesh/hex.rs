//! A mesh of triquadratic hexahedra: connectivity in tensor order, element faces, colours.

/// Nodes per element.
pub const NODES_PER_ELEMENT: usize = 27;

/// A face of an element: 9 nodes in tensor order (s, t) with ∂x/∂s × ∂x/∂t pointing out of the
/// element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// The element the face belongs to.
    pub element: usize,
    /// Local axis normal to the face (0 = ξ, 1 = η, 2 = ζ).
    pub axis: usize,
    /// Whether the face is at +1 (true) or −1 (false) along `axis`.
    pub positive: bool,
    /// Global node ids in face tensor order.
    pub nodes: [usize; 9],
}

/// A mesh of triquadratic hexahedra.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Reference node coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// Element connectivity (tensor order).
    pub elements: Vec<[usize; NODES_PER_ELEMENT]>,
    /// Element colours: no two elements of one colour share a node.
    pub colors: Vec<Vec<usize>>,
}

impl Mesh {
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// Greedy element colouring (deterministic: elements in order, smallest free colour).
    pub fn compute_colors(&mut self) {
        let mut node_elems: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (e, conn) in self.elements.iter().enumerate() {
            for &n in conn {
                node_elems[n].push(e);
            }
        }
        let mut color_of = vec![usize::MAX; self.elements.len()];
        let mut colors: Vec<Vec<usize>> = Vec::new();
        let mut used = Vec::new();
        for e in 0..self.elements.len() {
            used.clear();
            for &n in &self.elements[e] {
                for &o in &node_elems[n] {
                    if color_of[o] != usize::MAX {
                        used.push(color_of[o]);
                    }
                }
            }
            let c = (0..).find(|c| !used.contains(c)).unwrap_or(0);
            color_of[e] = c;
            if c == colors.len() {
                colors.push(Vec::new());
            }
            colors[c].push(e);
        }
        self.colors = colors;
    }
}

/// Local node index of tensor position (i, j, k).
#[inline]
pub fn local_index(i: usize, j: usize, k: usize) -> usize {
    i + 3 * j + 9 * k
}

/// The 9 local node indices of a face in outward tensor order.
pub fn face_local_nodes(axis: usize, positive: bool) -> [usize; 9] {
    let d1 = (axis + 1) % 3;
    let d2 = (axis + 2) % 3;
    let fixed = if positive { 2 } else { 0 };
    let mut out = [0; 9];
    for t in 0..3 {
        for s in 0..3 {
            // for the negative face swap s and t so that the normal points outwards
            let (a, b) = if positive { (s, t) } else { (t, s) };
            let mut ijk = [0; 3];
            ijk[axis] = fixed;
            ijk[d1] = a;
            ijk[d2] = b;
            out[s + 3 * t] = local_index(ijk[0], ijk[1], ijk[2]);
        }
    }
    out
}
