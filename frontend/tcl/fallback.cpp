// The Tcl text of fallback.h. The helper files' versions are written from slide.md §7.2–§7.4
// (what each proc does to globals and widgets), not copied: only what geometry depends on
// (the globals, their defaults, the scales bound to them) is reproduced; the widgets are
// the Tk stubs of interp.cpp.
#include "frontend/tcl/fallback.h"

namespace nomec::tcl {

namespace {

// The viewer's globals (slide.md §5, §6), the values nomec chooses for the enumerations whose
// values are unknown (docs/dialects.md), and the lost `slideui`/`parselib` packages.
constexpr std::string_view kPrelude = R"TCL(
set SLF_PI 3.14159265358979323846
set SLF_TIME 0
set SLF_FRAME 0
foreach {n v} {SLF_OFF 0 SLF_ON 1 SLF_SOLID 0 SLF_HOLLOW 1 SLF_INHERIT 0 SLF_WIRE 1 SLF_FLAT 2
    SLF_GOURAUD 3 SLF_PHONG 4 SLF_BOUND 1 SLF_EDGES 2 SLF_FULL 3 SLF_PARALLEL 0 SLF_PERSPECTIVE 1
    SLF_AMBIENT 0 SLF_DIRECTIONAL 1 SLF_POINT 2 SLF_SPOT 3
    SLF_NULL 0 SLF_TEXMAP 1 SLF_VERTEX_CORNER 1 SLF_QUADRILATERALS 1
    SLF_SUBDIVISION_CATMULL_CLARK 1 SLF_SUBDIVISION_CORNER_ROUNDING_TESSELATE 2
    SLF_OFFSET_ANGULAR 1 SLF_OFFSET_PERFORATED 2} { set $n $v }
unset n v

# The lost packages, defined when a scene requires them (slide.md §7.5).
package ifneeded parselib 1.0 {
# parselib's mesh import: `CreateSTLObject NAME FILE` (and `CreateSIFObject`) reads FILE next
# to the scene into the object `oNAME`, held by the group `gNAME` it returns.
foreach p {CreateSTLObject CreateSIFObject} {
  proc $p {name {file {}}} [string map [list @P@ $p] {
    if {[slide import $name $file]} { return g$name }
    slide create group g$name
    slide create object o$name {}
    slide unavailable @P@ $name $file
    return g$name
  }]
}
package provide parselib 1.0
}
package ifneeded slideui 1.0 {
package require parselib
# slideui's own CreateScale: PARENT THIS VARNAME TEXT MIN MAX RES [CMD]; the file presets VARNAME.
proc CreateScale {parent this var text min max res {cmd {}}} {
  scale $parent.$this -label $text -from $min -to $max -resolution $res -variable $var
}

proc CreateSLIDESubdivisionObject {name} {
  global $name SLF_FULL SLF_INHERIT SLF_SUBDIVISION_CATMULL_CLARK
  array set $name [list lod $SLF_FULL shading $SLF_INHERIT type $SLF_SUBDIVISION_CATMULL_CLARK \
      subdivisions 2 errormetric 0 drawcontrols 0 drawcurrent 1 drawvertices 0 weightededges 0 \
      weight 1.0 a 0.0 b 0.0 tolerance 0.0 facetsmax 0 uknots 0 uorder 0 vknots 0 vorder 0]
  return $name
}
proc CreateSLIDESubdivisionUI {parent name} {
  frame $parent.sub
  scale $parent.sub.levels -label Subdivisions -from 0 -to 5 -resolution 1 -variable ${name}(subdivisions)
  return $parent.sub
}
proc CreateSLIDEOffsetObject {name} {
  global $name SLF_FULL SLF_INHERIT SLF_OFFSET_ANGULAR
  array set $name [list lod $SLF_FULL shading $SLF_INHERIT type $SLF_OFFSET_ANGULAR height 0.1 width 0.05 \
      drawcontrols 0]
  return $name
}
proc CreateSLIDEOffsetUI {parent name} {
  frame $parent.off
  scale $parent.off.height -label Height -from 0 -to 1 -resolution 0.01 -variable ${name}(height)
  scale $parent.off.width -label Width -from 0 -to 1 -resolution 0.01 -variable ${name}(width)
  return $parent.off
}
proc CreateSLIDEObjectObject {name} {
  global $name SLF_FULL SLF_INHERIT SLF_SOLID
  array set $name [list lod $SLF_FULL shading $SLF_INHERIT solid $SLF_SOLID]
  global ${name}_lod ${name}_shading ${name}_solid
  set ${name}_lod $SLF_FULL
  set ${name}_shading $SLF_INHERIT
  set ${name}_solid $SLF_SOLID
  return $name
}
proc CreateSLIDEGroupUI {parent name} { frame $parent; return $parent }
# The two test grids, inferred from how subdivision.slf places them (docs/dialects.md):
# six `oGrid_3_3` moved by (0 0 1) and turned by 0, ±90, 180 degrees make the "Rubik's
# cube", so a grid spans [-1, 1]² at z = 0, facing +z; `gCubeGrid_2` is then the closed cube
# [-1, 1]³ with N × N quads on each side, one shared point per lattice point, facing out.
proc CreateSLIDEGrid {name nx ny} {
  set faces {}
  for {set i 0} {$i <= $nx} {incr i} {
    for {set j 0} {$j <= $ny} {incr j} {
      slide create point p${name}_${i}_$j [list [expr {-1.0 + 2.0 * $i / $nx}] [expr {-1.0 + 2.0 * $j / $ny}] 0.0]
    }
  }
  for {set i 0} {$i < $nx} {incr i} {
    for {set j 0} {$j < $ny} {incr j} {
      set i1 [expr {$i + 1}]
      set j1 [expr {$j + 1}]
      slide create face f${name}_${i}_$j [list p${name}_${i}_$j p${name}_${i1}_$j p${name}_${i1}_$j1 p${name}_${i}_$j1]
      lappend faces f${name}_${i}_$j
    }
  }
  slide create object o$name $faces
  slide create group g$name
  slide create instance i$name g$name o$name
  return g$name
}
proc CreateSLIDECubeGrid {name n} {
  set faces {}
  array set made {}
  # Each side: the axis it is normal to, the two axes (u, v) with u × v pointing out of the
  # far side (coordinate n); the near side (0) runs round the other way.
  foreach {axis u v} {0 1 2  1 2 0  2 0 1} {
    foreach side {0 1} {
      for {set a 0} {$a < $n} {incr a} {
        for {set b 0} {$b < $n} {incr b} {
          set corners {}
          foreach {da db} {0 0 1 0 1 1 0 1} {
            set c($axis) [expr {$side * $n}]
            set c($u) [expr {$a + $da}]
            set c($v) [expr {$b + $db}]
            set pt p${name}_$c(0)_$c(1)_$c(2)
            if {![info exists made($pt)]} {
              set made($pt) 1
              slide create point $pt [list [expr {-1.0 + 2.0 * $c(0) / $n}] [expr {-1.0 + 2.0 * $c(1) / $n}] \
                  [expr {-1.0 + 2.0 * $c(2) / $n}]]
            }
            lappend corners $pt
          }
          if {$side == 0} { set corners [lreverse $corners] }
          set f f${name}_${axis}_${side}_${a}_$b
          slide create face $f $corners
          lappend faces $f
        }
      }
    }
  }
  slide create object o$name $faces
  slide create group g$name
  slide create instance i$name g$name o$name
  return g$name
}
# The other test geometry and mesh import of the lost packages: an empty group `g<NAME>`, an
# empty object `o<NAME>`, and a note.
foreach p {CreateSLIDETetrahedralFrame CreateSLIDECubeFrame
    CreateSLIDECubeFrameWithCorners CreateSLIDEOctahedronFrame CreateSLIDEDodecaStar CreateSLIDEOctaStar
    CreateSLIDESTLFILE} {
  proc $p {args} [string map [list @P@ $p] {
    set name [lindex $args 0]
    if {$name eq ""} { set name Polyhedrons }
    slide create group g$name
    slide create object o$name {}
    slide unavailable @P@ $name [lindex $args 1]
    return g$name
  }]
}
proc CreateSLIDEPolyhedrons {args} { slide create group gPolyhedrons; slide unavailable CreateSLIDEPolyhedrons Polyhedrons; return gPolyhedrons }
package provide slideui 1.0
}
)TCL";

constexpr std::string_view kSlfConsts = R"TCL(
foreach {n v} {SLF_OFF 0 SLF_ON 1 SLF_SOLID 0 SLF_HOLLOW 1 SLF_INHERIT 0 SLF_WIRE 1 SLF_FLAT 2
    SLF_GOURAUD 3 SLF_PHONG 4 SLF_BOUND 1 SLF_EDGES 2 SLF_FULL 3 SLF_PARALLEL 0 SLF_PERSPECTIVE 1
    SLF_AMBIENT 0 SLF_DIRECTIONAL 1 SLF_POINT 2 SLF_SPOT 3} { set ::$n $v }
)TCL";

constexpr std::string_view kMath = R"TCL(
proc DegToRad {d} { expr {$d * $::SLF_PI / 180} }
proc RadToDeg {r} { expr {$r * 180 / $::SLF_PI} }
proc Min {a b} { if {$b < $a} { return $b }; return $a }
proc Max {a b} { if {$b > $a} { return $b }; return $a }
proc Oscillate {} { expr {(cos($::SLF_TIME) + 1) / 2} }
)TCL";

// SLIDEUI.tcl: the panels set `${name}_${this}` globals and bind scales and radio buttons.
constexpr std::string_view kSlideUi = R"TCL(
source SLFCONSTS.tcl
source MATH.tcl
proc CalculateTickInterval {min max tickints} { expr {($max - $min) / $tickints} }
proc CreateSLIDEEnumList {fields} {
  set out {}
  foreach f $fields { lappend out [list $f [set ::$f]] }
  return $out
}
proc CreateRadioButtonFrame {name parent this text default enumList} {
  set root $parent.$this
  frame $root
  set ::${name}_${this} $default
  label $root.title -text $text
  foreach choice $enumList {
    radiobutton $root.slf[lindex $choice 0] -variable ${name}_${this} -value [lindex $choice 1]
  }
  return $root
}
proc CreateScale {name parent this text default min max resolution tickints orient} {
  set ::${name}_${this} $default
  scale $parent.$this -label $text -from $min -to $max -resolution $resolution -variable ${name}_${this}
}
proc CreateScaleCmd {name parent this text default min max resolution tickints orient cmd} {
  set ::${name}_${this} $default
  scale $parent.$this -label $text -from $min -to $max -resolution $resolution -variable ${name}_${this} -command $cmd
}
proc CreateDoubleScale {name parent this thisA thisB textA textB min defaultA defaultB max resolution tickints orient} {
  set ::${name}_${thisA} $defaultA
  set ::${name}_${thisB} $defaultB
  frame $parent.$this
  scale $parent.$this.$thisA -from $min -to [expr {$defaultB - abs($resolution)}] -resolution $resolution -variable ${name}_${thisA}
  scale $parent.$this.$thisB -from [expr {$defaultA + abs($resolution)}] -to $max -resolution $resolution -variable ${name}_${thisB}
  return $parent.$this
}
proc CreateLODFrame {name parent} { CreateRadioButtonFrame $name $parent lod LOD $::SLF_FULL [CreateSLIDEEnumList {SLF_OFF SLF_BOUND SLF_EDGES SLF_FULL}] }
proc CreateShadingFrame {name parent} { CreateRadioButtonFrame $name $parent shading Shading $::SLF_INHERIT [CreateSLIDEEnumList {SLF_INHERIT SLF_WIRE SLF_FLAT SLF_GOURAUD SLF_PHONG}] }
proc CreateSolidFrame {name parent} { CreateRadioButtonFrame $name $parent solid Solid $::SLF_SOLID [CreateSLIDEEnumList {SLF_SOLID SLF_HOLLOW}] }
proc CreateProjectionFrame {name parent} { CreateRadioButtonFrame $name $parent projection Projection $::SLF_PERSPECTIVE [CreateSLIDEEnumList {SLF_PERSPECTIVE SLF_PARALLEL}] }
proc CreateLightTypeFrame {name parent} { CreateRadioButtonFrame $name $parent type Type $::SLF_AMBIENT [CreateSLIDEEnumList {SLF_AMBIENT SLF_DIRECTIONAL SLF_POINT SLF_SPOT}] }
proc SlfPanelRoot {parent name} {
  if {$parent eq {} || $parent eq "."} { return .slf_$name }
  return $parent.slf_$name
}
proc CreateGroupUI {parent name} {
  set root [SlfPanelRoot $parent $name]
  toplevel $root
  CreateLODFrame $name $root
  CreateShadingFrame $name $root
  return $root
}
proc CreateInstanceUI {parent name} { CreateGroupUI $parent $name }
proc CreateObjectUI {parent name} {
  set root [CreateGroupUI $parent $name]
  CreateSolidFrame $name $root
  return $root
}
proc CreateCameraUI {parent name} {
  set root [SlfPanelRoot $parent $name]
  toplevel $root
  CreateProjectionFrame $name $root
  CreateDoubleScale $name $root lr left right Left Right -1 -0.5 0.5 1 0.01 4 horizontal
  CreateDoubleScale $name $root bt bottom top Bottom Top -1 -0.5 0.5 1 0.01 4 horizontal
  CreateDoubleScale $name $root bf back front Back Front -10 -2 -0.01 0 0.01 4 horizontal
  return $root
}
proc CreateRGBColorUI {name parent this} {
  frame $parent.$this
  foreach c {r g b} { CreateScale $name $parent.$this color_$c $c 0.5 0 1 0.01 4 horizontal }
  return $parent.$this
}
proc CreateRGBColorButton {name parent this text} { button $parent.$this -text $text; return $parent.$this }
proc CBRGBColor {root name value} {}
proc RGBScaleToByte {value} { expr {int($value * 255)} }
proc CreateLightUI {parent name} {
  set root [SlfPanelRoot $parent $name]
  toplevel $root
  CreateLightTypeFrame $name $root
  CreateRGBColorUI $name $root color
  CreateScale $name $root d0 "Dead Distance" 0.1 0 10 0.01 4 horizontal
  CreateScale $name $root n1 "Fall Off" 1 0 10 0.01 4 horizontal
  CreateScale $name $root n2 "Angular Fall Off" 1 0 10 0.01 4 horizontal
  return $root
}
proc CreateSurfaceUI {parent name} {
  set root [SlfPanelRoot $parent $name]
  toplevel $root
  CreateRGBColorUI $name $root color
  foreach {v t} {kAmb Ambient kDiff Diffuse kSpec Specular nPhong Phong f Metallic} {
    CreateScale $name $root $v $t 1 0 1 0.01 4 horizontal
  }
  return $root
}
)TCL";

// MOVIE.tcl: the frame slider and the playback globals; `MovieUpdate` advances nothing in
// a static compile (nothing plays).
constexpr std::string_view kMovie = R"TCL(
proc CreateMovieUI {parent name min max winx winy} {
  global framesWritten delayWrite oneMore minFrame maxFrame start end play writeRib
  set framesWritten 0; set delayWrite 0; set oneMore 0; set play 0
  if {$max < $min} { set minFrame $max; set maxFrame $min } else { set minFrame $min; set maxFrame $max }
  set start $minFrame; set end $maxFrame
  set root .slf_$name
  if {$parent ne {} && $parent ne "."} { set root $parent.slf_$name }
  toplevel $root
  set ::${name}_frame $minFrame
  scale $root.frame -from $minFrame -to $maxFrame -resolution 1 -variable ${name}_frame
  checkbutton $root.write -variable writeRib
  return $root
}
proc MovieUpdate {} {}
proc PlayMovie {} {}
proc WriteRibFile {} {}
)TCL";

}  // namespace

std::string_view prelude_script() { return kPrelude; }

std::optional<std::string_view> fallback_script(std::string_view base_name) {
  if (base_name == "SLIDEUI.tcl") return kSlideUi;
  if (base_name == "MATH.tcl") return kMath;
  if (base_name == "SLFCONSTS.tcl") return kSlfConsts;
  if (base_name == "MOVIE.tcl") return kMovie;
  return std::nullopt;
}

}  // namespace nomec::tcl
