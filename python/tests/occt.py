"""Reading STEP files back with OCCT (cadquery-ocp): solids, validity, volume, tight boxes."""
from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.Bnd import Bnd_Box
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_SHELL, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.BRep import BRep_Tool


def read_solids(path):
    """All solids of a STEP file (assembly occurrences placed), and the file's shape."""
    r = STEPControl_Reader()
    assert r.ReadFile(str(path)) == IFSelect_RetDone, path
    r.TransferRoots()
    shape = r.OneShape()
    out, ex = [], TopExp_Explorer(shape, TopAbs_SOLID)
    while ex.More():
        out.append(TopoDS.Solid(ex.Current()))
        ex.Next()
    return shape, out


def is_valid(shape):
    return BRepCheck_Analyzer(shape).IsValid()


def closed_shells(solid):
    ex, flags = TopExp_Explorer(solid, TopAbs_SHELL), []
    while ex.More():
        flags.append(BRep_Tool.IsClosed_s(ex.Current()))
        ex.Next()
    return flags


def volume(shape):
    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, g)
    return g.Mass()


def bbox(shape):
    """Tight box (xmin, ymin, zmin, xmax, ymax, zmax), mm."""
    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False, False)
    lo, hi = b.CornerMin(), b.CornerMax()
    return (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z())


def common_volume(a, b):
    op = BRepAlgoAPI_Common(a, b)
    assert op.IsDone()
    return volume(op.Shape())
