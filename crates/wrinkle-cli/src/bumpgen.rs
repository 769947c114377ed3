//! `wrinkle bumpgen`: write a generated bump-function table (Blinn 1978, figs. 5-8) as a 16-bit grey PNG.

use std::path::PathBuf;

use wrinkle::bump::generators::{BrickParams, Generator, GridParams, RivetParams, TextParams};

/// Which table to generate.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A gridwork of high lines on a low floor (fig. 5)
    Grid,
    /// Embossed bitmap letters in one row (fig. 6)
    Text,
    /// The Z-buffer of a sphere replicated into rivets (fig. 7)
    Rivets,
    /// A running-bond brick unit cell (fig. 8)
    Bricks,
}

/// Generate a tileable bump-function table and write it as a 16-bit grey PNG (white is high).
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Options that do not belong to the chosen kind are ignored.

Examples:
  wrinkle bumpgen grid -o grid.png --size 512 --cells 8 --line-width 0.2
  wrinkle bumpgen text -o title.png --size 128 --text \"SIGGRAPH 78\"
  wrinkle bumpgen bricks -o bricks.png --rows 8 --bricks-per-row 3 --mortar 0.1")]
pub struct BumpgenArgs {
    /// The pattern to generate
    #[arg(value_enum)]
    pub kind: Kind,
    /// Output PNG file
    #[arg(short, long)]
    pub output: PathBuf,
    /// Side of the table in texels (for text, its height; the width is SIZE per letter)
    #[arg(long, default_value_t = 512)]
    pub size: usize,
    /// grid: cells along each side
    #[arg(long, default_value_t = GridParams::default().cells)]
    pub cells: usize,
    /// grid: fraction of a cell covered by each line
    #[arg(long, allow_negative_numbers = true, default_value_t = GridParams::default().line_width)]
    pub line_width: f32,
    #[arg(long, allow_negative_numbers = true, help = format!(
        "grid: width of the edge ramp as a fraction of a cell; text: blur radius as a fraction of a glyph pixel \
         [default: {} for grid, {} for text]",
        GridParams::default().soft,
        TextParams::default().soft
    ))]
    pub soft: Option<f32>,
    /// text: the letters (ASCII; other characters become '?')
    #[arg(long, default_value_t = TextParams::default().text)]
    pub text: String,
    /// rivets: rivets along each side (must divide SIZE)
    #[arg(long, default_value_t = RivetParams::default().count)]
    pub count: usize,
    /// rivets: radius as a fraction of a rivet's cell
    #[arg(long, allow_negative_numbers = true, default_value_t = RivetParams::default().radius)]
    pub radius: f32,
    /// bricks: courses of bricks (even)
    #[arg(long, default_value_t = BrickParams::default().rows)]
    pub rows: usize,
    /// bricks: bricks in each course
    #[arg(long, default_value_t = BrickParams::default().bricks_per_row)]
    pub bricks_per_row: usize,
    /// bricks: mortar joint width as a fraction of a course's height
    #[arg(long, allow_negative_numbers = true, default_value_t = BrickParams::default().mortar)]
    pub mortar: f32,
    /// bricks: bevel width as a fraction of a course's height
    #[arg(long, allow_negative_numbers = true, default_value_t = BrickParams::default().bevel)]
    pub bevel: f32,
}

impl BumpgenArgs {
    /// The generator named by `kind` with the options that belong to it.
    fn generator(&self) -> Generator {
        match self.kind {
            Kind::Grid => Generator::Grid(GridParams {
                cells: self.cells,
                line_width: self.line_width,
                soft: self.soft.unwrap_or(GridParams::default().soft),
            }),
            Kind::Text => Generator::Text(TextParams {
                text: self.text.clone(),
                soft: self.soft.unwrap_or(TextParams::default().soft),
            }),
            Kind::Rivets => Generator::Rivets(RivetParams { count: self.count, radius: self.radius }),
            Kind::Bricks => Generator::Bricks(BrickParams {
                rows: self.rows,
                bricks_per_row: self.bricks_per_row,
                mortar: self.mortar,
                bevel: self.bevel,
            }),
        }
    }
}

/// Generate the table and write it to `args.output`.
pub fn run(args: &BumpgenArgs) -> wrinkle::Result<()> {
    crate::output::require_extension(&args.output, &["png"])?;
    let table = args.generator().generate(args.size)?;
    wrinkle::image::io::write_png_grey16(&args.output, &table)?;
    println!("wrote {} ({}x{}, 16-bit grey)", args.output.display(), table.width, table.height);
    Ok(())
}
