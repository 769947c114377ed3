//! Scenes built in code: validated constructors for the camera, its projection and the lights, and a
//! scene that grows object by object. The TOML loader (load.rs) builds through the same constructors, so a
//! value is checked in one place whichever front end gave it; their errors name the parameter
//! (`Error::Parameter`), and the loader words the name as the field's path.

use super::{CameraDesc, Object, Scene};
use crate::error::{Error, Result};
use crate::geometry::{Shape, Transform};
use crate::light::{Light, ShadowSettings, Spot};
use crate::raster::Projection;
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

    /// Adds `shape`, placed by `transform`, of the material at index `material`; returns its index.
    pub fn add_object(&mut self, shape: Shape, transform: Transform, material: usize) -> Result<usize> {
        if material >= self.materials.len() {
            return Err(Error::parameter(
                "material",
                format!("must index one of the scene's {} materials, got {material}", self.materials.len()),
            ));
        }
        self.objects.push(Object { shape, transform, material, affine: false });
        Ok(self.objects.len() - 1)
    }
}
