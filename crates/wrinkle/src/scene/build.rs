//! Scenes built in code: validated constructors for the camera, its projection and the lights, and a
//! scene that grows object by object. The TOML loader (load.rs) builds through the same constructors, so a
//! value is checked in one place whichever front end gave it; their errors name the parameter
//! (`Error::Parameter`), and the loader words the name as the field's path.

use super::{CameraDesc, Object, Scene};
use crate::error::{Error, Result};
use crate::geometry::billboard::Billboard;
use crate::geometry::{MeshPart, Shape, Surface, Transform};
use crate::light::{Light, ShadowSettings, Spot};
use crate::raster::{Camera, Projection};
use crate::shade::Material;
use glam::Vec3;

/// A colour or a radiance: three finite, non-negative components.
pub(crate) fn check_colour(name: &'static str, c: Vec3) -> Result<Vec3> {
    if !c.is_finite() || c.min_element() < 0.0 {
        return Err(Error::parameter(
            name,
            format!("must have non-negative colour components, got [{}, {}, {}]", c.x, c.y, c.z),
        ));
    }
    Ok(c)
}

fn check_point(name: &'static str, p: Vec3) -> Result<Vec3> {
    if !p.is_finite() {
        return Err(Error::parameter(name, format!("must be finite, got [{}, {}, {}]", p.x, p.y, p.z)));
    }
    Ok(p)
}

/// A direction of any non-zero finite length, made unit.
fn check_direction(name: &'static str, d: Vec3) -> Result<Vec3> {
    check_point(name, d)?.try_normalize().ok_or_else(|| Error::parameter(name, "must not be [0, 0, 0]"))
}

fn check_length(name: &'static str, x: f32) -> Result<f32> {
    if !(x > 0.0 && x.is_finite()) {
        return Err(Error::parameter(name, format!("must be a positive length, got {x}")));
    }
    Ok(x)
}

fn check_points(name: &'static str, points: &[Vec3]) -> Result<()> {
    match points.iter().find(|p| !p.is_finite()) {
        Some(p) => Err(Error::parameter(name, format!("must be finite points, got [{}, {}, {}]", p.x, p.y, p.z))),
        None => Ok(()),
    }
}

impl Shape {
    /// The shape if its sizes are positive and its points finite, a billboard's axis made unit.
    pub fn validated(self) -> Result<Shape> {
        match self {
            Shape::Surface(ref s) => {
                match *s {
                    Surface::Sphere { radius } => check_length("radius", radius).map(drop)?,
                    Surface::Cylinder { radius, height } => {
                        check_length("radius", radius)?;
                        check_length("height", height)?;
                    }
                    Surface::Torus { major_radius, minor_radius } => {
                        check_length("major_radius", major_radius)?;
                        check_length("minor_radius", minor_radius)?;
                    }
                    Surface::Patch { ref corners } => check_points("corners", corners)?,
                    Surface::Bicubic { ref points } => check_points("points", points)?,
                }
                Ok(self)
            }
            Shape::Box { size } => {
                if !(size.is_finite() && size.min_element() > 0.0) {
                    let message = format!("must be positive edge lengths, got [{}, {}, {}]", size.x, size.y, size.z);
                    return Err(Error::parameter("size", message));
                }
                Ok(self)
            }
            Shape::Billboard(b) => {
                let axis = check_point("axis", b.axis)?
                    .try_normalize()
                    .ok_or_else(|| Error::parameter("axis", "must be a direction, not [0, 0, 0]"))?;
                Ok(Shape::Billboard(Billboard {
                    width: check_length("width", b.width)?,
                    height: check_length("height", b.height)?,
                    axis,
                    ..b
                }))
            }
            // A mesh was validated when it was made (`TriangleMesh::new`).
            Shape::Mesh(_) => Ok(self),
        }
    }
}

impl Transform {
    /// The transform if it is finite and scales by no zero.
    pub fn validated(self) -> Result<Transform> {
        check_point("translate", self.translate)?;
        check_point("rotate", self.rotate)?;
        if !self.scale.is_finite() || self.scale.abs().min_element() == 0.0 {
            let s = self.scale;
            return Err(Error::parameter(
                "scale",
                format!("must be finite and not zero along any axis, got [{}, {}, {}]", s.x, s.y, s.z),
            ));
        }
        Ok(self)
    }
}

impl Projection {
    /// A perspective projection of `fov_y` degrees vertically, strictly between 0 and 180.
    pub fn perspective(fov_y: f32) -> Result<Projection> {
        if !(fov_y > 0.0 && fov_y < 180.0) {
            return Err(Error::parameter("fov_y", format!("must be degrees between 0 and 180, got {fov_y}")));
        }
        Ok(Projection::Perspective { fov_y })
    }

    /// An orthographic projection seeing `height` world units vertically.
    pub fn orthographic(height: f32) -> Result<Projection> {
        if !(height > 0.0 && height.is_finite()) {
            return Err(Error::parameter("height", format!("must be a positive height, got {height}")));
        }
        Ok(Projection::Orthographic { height })
    }
}

impl Default for Projection {
    /// 40 degrees vertically, as a scene's camera has unless it says otherwise.
    fn default() -> Self {
        Projection::Perspective { fov_y: 40.0 }
    }
}

impl CameraDesc {
    /// A camera at `eye` looking at `look_at`, `up` giving the picture's up (not along the view), and a
    /// background (linear RGB) where it sees nothing.
    pub fn new(eye: Vec3, look_at: Vec3, up: Vec3, projection: Projection, background: Vec3) -> Result<CameraDesc> {
        let view = check_point("look_at", look_at)? - check_point("eye", eye)?;
        if view.length() == 0.0 {
            return Err(Error::parameter("look_at", "must differ from eye"));
        }
        if view.normalize().cross(check_point("up", up)?).length() < 1e-6 {
            return Err(Error::parameter("up", "must not be parallel to the view direction"));
        }
        let projection = match projection {
            Projection::Perspective { fov_y } => Projection::perspective(fov_y)?,
            Projection::Orthographic { height } => Projection::orthographic(height)?,
        };
        Ok(CameraDesc { eye, look_at, up, projection, background: check_colour("background", background)? })
    }

    /// A camera at `eye` looking at `look_at`, +Y up, 40 degrees vertically, a black background.
    pub fn looking_at(eye: Vec3, look_at: Vec3) -> Result<CameraDesc> {
        CameraDesc::new(eye, look_at, Vec3::Y, Projection::default(), Vec3::ZERO)
    }

    /// The camera a frame of `width` x `height` pixels is rendered through: where world points land on the
    /// screen and the ray through a pixel (what picking under the mouse needs).
    pub fn screen(&self, width: usize, height: usize) -> Camera {
        Camera::new(self.eye, self.look_at, self.up, self.projection, width as u32, height as u32)
    }
}

impl Default for CameraDesc {
    /// Four units down +Z looking at the origin: a unit sphere there fills half the picture's height.
    fn default() -> Self {
        CameraDesc::looking_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO).expect("the default camera is valid")
    }
}

impl Light {
    /// Light travelling along `direction` (any non-zero length) with `radiance` (colour x intensity).
    pub fn directional(direction: Vec3, radiance: Vec3) -> Result<Light> {
        Ok(Light::Directional {
            direction: check_direction("direction", direction)?,
            radiance: check_colour("radiance", radiance)?,
        })
    }

    /// A point light at `position`; its `radiance` falls off with the square of the distance.
    pub fn point(position: Vec3, radiance: Vec3) -> Result<Light> {
        Ok(Light::Point { position: check_point("position", position)?, radiance: check_colour("radiance", radiance)? })
    }

    /// Light from everywhere, reflected diffusely without regard to the normal.
    pub fn ambient(radiance: Vec3) -> Result<Light> {
        Ok(Light::Ambient { radiance: check_colour("radiance", radiance)? })
    }

    /// A spot light at `position` shining along `direction` in a cone of `angle` degrees from its axis
    /// (above 0, below 89), its edge softened over the last `falloff` degrees (0 to `angle`); `up` turns a
    /// projected slide (`Spot::slide`) upright.
    pub fn spot(position: Vec3, direction: Vec3, up: Vec3, angle: f32, falloff: f32, radiance: Vec3) -> Result<Light> {
        let direction = check_direction("direction", direction)?;
        if !(angle > 0.0 && angle < 89.0) {
            return Err(Error::parameter(
                "angle",
                format!("must be degrees from the axis, above 0 and below 89, got {angle}"),
            ));
        }
        if !(falloff >= 0.0 && falloff <= angle) {
            return Err(Error::parameter(
                "falloff",
                format!("must be degrees from 0 to the cone's angle ({angle}), got {falloff}"),
            ));
        }
        let (position, up, radiance) =
            (check_point("position", position)?, check_point("up", up)?, check_colour("radiance", radiance)?);
        Ok(Light::Spot(Spot::new(position, direction, up, angle, falloff, radiance)))
    }
}

impl Scene {
    /// An empty scene seen by `camera`: add lights, materials and objects to it.
    pub fn new(camera: CameraDesc) -> Scene {
        Scene {
            camera,
            lights: Vec::new(),
            shadows: Vec::new(),
            objects: Vec::new(),
            materials: Vec::new(),
            volumes: Vec::new(),
            environment: None,
            slides: Vec::new(),
            animation: None,
        }
    }

    /// Adds a light that casts shadows as lights do by default.
    pub fn add_light(&mut self, light: Light) -> &mut Scene {
        self.add_light_with(light, ShadowSettings::default())
    }

    /// Adds a light with its own shadow settings.
    pub fn add_light_with(&mut self, light: Light, shadows: ShadowSettings) -> &mut Scene {
        self.lights.push(light);
        self.shadows.push(shadows);
        self
    }

    /// Adds a material and returns its index, for [`Scene::add_object`].
    pub fn add_material(&mut self, material: Material) -> usize {
        self.materials.push(material);
        self.materials.len() - 1
    }

    /// Adds `shape`, placed by `transform`, of the material at index `material` (a mesh's parts name their
    /// own); returns its index.
    pub fn add_object(&mut self, shape: Shape, transform: Transform, material: usize) -> Result<usize> {
        let count = self.materials.len();
        let parts: &[MeshPart] = if let Shape::Mesh(parts) = &shape { parts } else { &[] };
        if let Some(m) = std::iter::once(material).chain(parts.iter().map(|p| p.material)).find(|&m| m >= count) {
            return Err(Error::parameter(
                "material",
                format!("must index one of the scene's {count} materials, got {m}"),
            ));
        }
        let (shape, transform) = (shape.validated()?, transform.validated()?);
        self.objects.push(Object { shape, transform, material, affine: false });
        Ok(self.objects.len() - 1)
    }
}
