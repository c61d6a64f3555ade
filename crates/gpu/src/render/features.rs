//! What a scene uses of the render shader, as WGSL constants: `shaders/render.wgsl` declares
//! `RD_USE_*` and `RD_OCC_*` true, and guards each optional part with its constant (`if
//! RD_USE_BUMP && object.flags.z != 0u`); [`Features::apply`] sets false the constants of the
//! parts no object of the scene needs, so that the compiler drops their code.
//!
//! Why: lavapipe (Mesa 22's llvmpipe) runs a fragment's branches as masked SIMD code, both
//! sides whatever the condition, so every optional part (micro-relief,
//! textures, glTF maps, the shadow rays' mesh traversal and its 64-entry stack) cost every
//! fragment of every scene. Measured on lavapipe (2 cores; `tools/render_speed.sh OLD NEW 5
//! -- --model cook-torrance --param d=ggx --param alpha=0.3 --size 512x512 --spp 2 --gpu`,
//! the GPU's draws, medians of 5 interleaved runs): the sphere 3.98x faster under the key
//! light and 4.20x under the sky (`--env sky --env-samples 8`), the face 1.37x and 1.43x (its
//! shadow rays' BVH walks are most of its time, and stay). A GPU with real branches skips the
//! parts at run time either way; there the constants shorten the compile and may lower the
//! registers a fragment holds. On SwiftShader (the explorer's page) leaving out the glTF
//! maps' code was not measurably faster.
//!
//! The constants are decided from the same words the shader tests ([`Features::new`] reads
//! the objects' uniforms and occluder records), so a part is off only where every object's
//! own flag would skip it: the picture is the same to the bit. The shadow rays are off where
//! no object can be shadowed (`Scene::may_shadow`: a lone plane, or a lone sphere seen from
//! outside, whose own points it never shadows), as the CPU renderer skips them.

use fastbrdf_render::geometry::BVH_STACK;
use fastbrdf_render::scene::{Scene, Shape};
use std::sync::atomic::{AtomicBool, Ordering};

static FORCE_ALL: AtomicBool = AtomicBool::new(false);

/// Every part on in every render of this process from now on (the shader as written, as
/// before the constants), for the tests that hold the per-scene shader to the same bits.
#[doc(hidden)]
pub fn force_all(on: bool) {
    FORCE_ALL.store(on, Ordering::Relaxed);
}

/// Per constant: its name and the member, component and word of `struct Object` (the
/// uniform, `objects::object_data`'s layout) whose non-zero value turns the part on for that
/// object (the test `object_words_are_the_shaders` holds the words to the shader's layout).
const OBJECT_FLAGS: [(&str, &str, usize, usize); 9] = [
    ("RD_USE_TEXTURE", "flags", 1, 29),
    ("RD_USE_BUMP", "flags", 2, 30),
    ("RD_USE_UVS", "flags", 3, 31),
    ("RD_USE_TANGENTS", "tex_size", 3, 35),
    ("RD_USE_TINT", "tint", 3, 39),
    ("RD_USE_NORMAL_MAP", "normal_map", 3, 43),
    ("RD_USE_OCCLUSION", "occlusion", 3, 47),
    ("RD_USE_EMISSIVE", "emissive", 3, 51),
    ("RD_USE_MR", "mr", 3, 67),
];

/// The occluder kinds (`struct Occluder`'s `kind.x`, word [`KIND_WORD`] of its record).
const OCCLUDER_KINDS: [(&str, u32); 3] = [
    ("RD_OCC_SPHERES", 0),
    ("RD_OCC_PLANES", 1),
    ("RD_OCC_MESHES", 2),
];

const KIND_WORD: usize = 8;

const SHADOWS: &str = "RD_USE_SHADOWS";

/// The mesh traversal's stack as written (`rd_occ_mesh`: 64 entries, `BVH_STACK`) and its
/// test for room; [`Features::apply`] sizes both for the scene's deepest BVH.
const MESH_STACK: &str = "var stack: array<u32, 64>;";
const MESH_STACK_ROOM: &str = "sp < 64u";

/// Which constants are true: by name, in the order of the shader's block.
#[derive(Clone, Debug)]
pub struct Features {
    on: Vec<(&'static str, bool)>,
    /// Entries of the mesh traversal's stack: the walk (`rd_occ_mesh`, the CPU's
    /// `occluded_binary`) keeps one child per inner node on its path, at most depth entries
    /// (`fastbrdf_render::geometry::BVH_STACK`), so the deepest mesh's depth + 1 never fills
    /// it, as 64 never fills on the CPU (the build bounds every depth by 62): the same walk.
    /// Fewer entries cost less to zero and index on adapters that keep the array in memory
    /// (lavapipe: 1.18x on the face under the sky).
    stack: usize,
}

impl Features {
    /// Every part on: the shader as written (what a module for unknown scenes takes).
    pub fn all() -> Self {
        let names = OBJECT_FLAGS
            .iter()
            .map(|&(n, ..)| n)
            .chain([SHADOWS])
            .chain(OCCLUDER_KINDS.iter().map(|&(n, _)| n));
        Self {
            on: names.map(|n| (n, true)).collect(),
            stack: BVH_STACK,
        }
    }

    /// The parts a scene needs: an object flag where some object's uniform (`objects`) has
    /// it; the shadow rays where `scene.shadows` and some object may be shadowed; an
    /// occluder kind where a record of `occluders` (`scene_data::OccluderData`) has it.
    pub(super) fn new<'a>(
        scene: &Scene,
        objects: impl IntoIterator<Item = &'a [u32]>,
        occluders: &[[u32; 12]],
    ) -> Self {
        let mut f = Self::all();
        if FORCE_ALL.load(Ordering::Relaxed) {
            return f;
        }
        let objects: Vec<&[u32]> = objects.into_iter().collect();
        for &(name, _, _, word) in &OBJECT_FLAGS {
            f.set(name, objects.iter().any(|u| u[word] != 0));
        }
        let shadows = scene.shadows && (0..scene.objects.len()).any(|i| scene.may_shadow(i));
        f.set(SHADOWS, shadows);
        for &(name, kind) in &OCCLUDER_KINDS {
            f.set(
                name,
                shadows && occluders.iter().any(|o| o[KIND_WORD] == kind),
            );
        }
        let depth = scene.objects.iter().filter_map(|o| match &o.shape {
            Shape::Mesh(m) if !m.triangles.is_empty() => Some(m.depth()),
            _ => None,
        });
        // At least 2 (one is never pushed on: the walk keeps at most depth entries).
        f.stack = depth.map(|d| d + 1).max().unwrap_or(0).clamp(2, BVH_STACK);
        f
    }

    /// Sets one constant (by its name in the shader).
    pub fn set(&mut self, name: &str, on: bool) {
        let slot = self.on.iter_mut().find(|(n, _)| *n == name);
        slot.unwrap_or_else(|| panic!("no feature {name}")).1 = on;
    }

    /// Whether a constant is true.
    pub fn get(&self, name: &str) -> bool {
        self.on.iter().any(|&(n, on)| n == name && on)
    }

    /// `shader` (`render.wgsl`) with these constants and the traversal's stack of
    /// [`Features::stack`] entries (2 without mesh occluders: SwiftShader was measured
    /// zero-initialising all 64 in every fragment even where the call is dead, about half of a
    /// frame of the explorer's page).
    pub fn apply(&self, shader: &str) -> String {
        let mut out = shader.to_string();
        for &(name, on) in &self.on {
            let written = format!("const {name}: bool = true;");
            assert!(
                out.matches(&written).count() == 1,
                "render.wgsl declares `{written}` once"
            );
            if !on {
                out = out.replace(&written, &format!("const {name}: bool = false;"));
            }
        }
        let stack = if self.get("RD_OCC_MESHES") {
            self.stack
        } else {
            2
        };
        for written in [MESH_STACK, MESH_STACK_ROOM] {
            assert!(
                out.matches(written).count() == 1,
                "render.wgsl's mesh stack moved: no `{written}`"
            );
            out = out.replace(written, &written.replace("64", &stack.to_string()));
        }
        out
    }

    /// The constants that are false, for messages and tests.
    pub fn off(&self) -> Vec<&'static str> {
        self.on
            .iter()
            .filter(|(_, on)| !on)
            .map(|&(n, _)| n)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::SHADER;
    use super::super::objects::Reach;
    use super::super::scene_data::OccluderData;
    use super::*;
    use fastbrdf::ModelSpec;
    use fastbrdf_render::bump::Bump;
    use fastbrdf_render::scene::Specular;
    use fastbrdf_render::setup::{self, SceneSpec};
    use std::path::PathBuf;
    use std::sync::Arc;

    /// `shader` with a black `rd_brdf`, parsed and validated (naga).
    fn module(shader: &str) -> naga::Module {
        super::super::naga_module(&format!("{shader}\n{}", super::super::env::BLACK_BRDF))
    }

    /// The word of `member` (component `c`, 4 bytes each) in the shader's struct `name`.
    fn word(module: &naga::Module, name: &str, member: &str, c: usize) -> usize {
        let (_, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no struct {name}"));
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            panic!("{name} is not a struct")
        };
        let m = members
            .iter()
            .find(|m| m.name.as_deref() == Some(member))
            .unwrap_or_else(|| panic!("no {name}.{member}"));
        m.offset as usize / 4 + c
    }

    /// The words the features read are those the shader's guards test.
    #[test]
    fn object_words_are_the_shaders() {
        let m = module(SHADER);
        for (name, member, c, w) in OBJECT_FLAGS {
            assert_eq!(word(&m, "Object", member, c), w, "{name}");
            let guard = format!("{name} && object.{member}.{}", ["x", "y", "z", "w"][c]);
            assert!(SHADER.contains(&guard), "render.wgsl has no `{guard}`");
        }
        assert_eq!(word(&m, "Occluder", "kind", 0), KIND_WORD);
    }

    fn scene(edit: impl FnOnce(&mut SceneSpec)) -> Scene {
        let mut spec = SceneSpec::new();
        edit(&mut spec);
        let model = ModelSpec::parse("cook-torrance", &[("alpha", "0.3")]).unwrap();
        let loaded = setup::load(&spec).unwrap();
        setup::scene(&spec, &loaded, Arc::new(Specular::new(&model).unwrap()))
    }

    /// What `render_scene` decides for `scene` (the same preparation of each object).
    fn features(scene: &Scene) -> Features {
        let limits = wgpu::Limits::default();
        let reach = Reach {
            eye: scene.camera.eye,
            sample_per_distance: 1e-3,
        };
        let data: Vec<_> = (scene.objects.iter().enumerate())
            .map(|(i, o)| {
                super::super::prepare(&limits, o, i, &reach, None)
                    .unwrap()
                    .data
            })
            .collect();
        let occluders = OccluderData::new(&limits, scene).unwrap();
        Features::new(
            scene,
            data.iter().map(|d| d.uniform.as_slice()),
            &occluders.objects,
        )
    }

    #[test]
    fn each_scene_gets_the_parts_it_uses() {
        let all = Features::all().off();
        assert!(all.is_empty());
        // The default scene, a lone sphere: nothing optional, no shadow rays (nothing else
        // can shadow it, as `Scene::may_shadow` says).
        let f = features(&scene(|_| {}));
        assert_eq!(f.off().len(), OBJECT_FLAGS.len() + 1 + OCCLUDER_KINDS.len());
        // On a floor, bumped: shadow rays between a sphere and a plane, micro-relief.
        let f = features(&scene(|s| {
            s.floor = true;
            s.bump = Some(Bump {
                scale: 8.0,
                depth: 0.1,
            });
        }));
        let on = |f: &Features, names: &[&str]| names.iter().all(|n| f.get(n));
        assert!(on(
            &f,
            &[
                "RD_USE_SHADOWS",
                "RD_OCC_SPHERES",
                "RD_OCC_PLANES",
                "RD_USE_BUMP"
            ]
        ));
        assert!(!f.get("RD_OCC_MESHES") && !f.get("RD_USE_TEXTURE") && !f.get("RD_USE_UVS"));
        // The eye inside a lone sphere: its far wall shadows it (`Scene::may_shadow`).
        let mut inside = scene(|_| {});
        inside.camera.eye = glam::Vec3::new(0.0, 0.1, 0.2);
        let f = features(&inside);
        assert!(f.get("RD_USE_SHADOWS") && f.get("RD_OCC_SPHERES"));
        // Shadows off: no shadow code whatever the objects.
        let f = features(&scene(|s| {
            s.floor = true;
            s.shadows = false;
        }));
        assert!(!f.get("RD_USE_SHADOWS") && !f.get("RD_OCC_SPHERES") && !f.get("RD_OCC_PLANES"));
        // The face, textured: a mesh occluder (it shadows itself), its uvs and the texture.
        let f = features(&scene(|s| {
            s.mesh = Some(PathBuf::from(setup::BUILTIN_MESH));
            s.texture = Some(PathBuf::from(setup::BUILTIN_TEXTURE));
        }));
        assert!(on(
            &f,
            &[
                "RD_USE_SHADOWS",
                "RD_OCC_MESHES",
                "RD_USE_UVS",
                "RD_USE_TEXTURE"
            ]
        ));
        assert!(!f.get("RD_OCC_SPHERES") && !f.get("RD_USE_BUMP") && !f.get("RD_USE_TANGENTS"));
    }

    /// Every constant is written once, set as asked, and the module still validates; with
    /// every part on, the shader is unchanged.
    #[test]
    fn apply_sets_the_constants() {
        assert_eq!(Features::all().apply(SHADER), SHADER);
        let f = features(&scene(|_| {}));
        let src = f.apply(SHADER);
        for name in f.off() {
            assert!(
                src.contains(&format!("const {name}: bool = false;")),
                "{name}"
            );
        }
        assert!(src.contains("var stack: array<u32, 2>;") && src.contains("sp < 2u"));
        module(&src);
        // The face: its BVH's depth + 1 entries.
        let face = scene(|s| s.mesh = Some(PathBuf::from(setup::BUILTIN_MESH)));
        let Shape::Mesh(m) = &face.objects[0].shape else {
            panic!("the face is a mesh")
        };
        let f = features(&face);
        assert_eq!(f.stack, m.depth() + 1);
        assert!((3..BVH_STACK).contains(&f.stack), "{}", f.stack);
        let src = f.apply(SHADER);
        assert!(src.contains(&format!("var stack: array<u32, {}>;", f.stack)));
        assert!(src.contains(&format!("sp < {}u", f.stack)));
        module(&src);
    }
}
