//! Typed element ids: `u32` newtypes so a vertex id can never be passed
//! where a face id is meant. Meshes are limited to `u32::MAX - 1` elements.

use std::fmt;

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident, $prefix:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        #[derive(serde::Serialize, serde::Deserialize)]
        #[serde(transparent)]
        pub struct $name(pub u32);

        impl $name {
            /// The id as an index into the owning array.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }
            /// Builds an id from an array index. Panics only if `i` does not
            /// fit in `u32`, which the loaders rule out before building ids.
            #[inline]
            pub fn from_idx(i: usize) -> Self {
                Self(u32::try_from(i).expect("element index exceeds u32"))
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($prefix, "{}"), self.0)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($prefix, "{}"), self.0)
            }
        }
    };
}

id_type!(
    /// A vertex of the mesh (index into `Mesh::positions`).
    VertexId,
    "v"
);
id_type!(
    /// A triangle of the mesh (index into `Mesh::faces`).
    FaceId,
    "f"
);
id_type!(
    /// An undirected edge of the mesh (index into `Topology::edges`).
    EdgeId,
    "e"
);
