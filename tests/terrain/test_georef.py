"""seismo3d.terrain.georef: GeoKeys, WKT, metres per degree, the local frame."""

import numpy as np
import pytest

from seismo3d.errors import InputError
from seismo3d.terrain.georef import (
    CoordinateReference,
    LocalFrame,
    check_compatible,
    encode_geokeys,
    geokeys_for,
    metres_per_degree,
    parse_geokeys,
    parse_wkt,
    reference_from_geokeys,
)

# The Autzen tile's WKT (LAS VLR), verbatim in structure: a user-defined Lambert conformal conic CRS in feet.
AUTZEN_WKT = ('PROJCS["NAD_1983_HARN_Lambert_Conformal_Conic",GEOGCS["GCS_North_American_1983_HARN",DATUM["NAD83_'
              'High_Accuracy_Regional_Network",SPHEROID["GRS_1980",6378137,298.257222101,AUTHORITY["EPSG","7019"]],'
              'AUTHORITY["EPSG","6152"]],PRIMEM["Greenwich",0],UNIT["degree",0.0174532925199433]],PROJECTION["Lambe'
              'rt_Conformal_Conic_2SP"],PARAMETER["standard_parallel_1",43],PARAMETER["false_easting",1312335.958005'
              '249],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]]]')


@pytest.mark.slow
def test_parse_wkt_projected_feet_without_epsg():
    from pyproj import CRS

    crs = parse_wkt(AUTZEN_WKT)
    assert crs.kind == "projected" and crs.linear_unit == "foot" and crs.unit_to_metre == pytest.approx(0.3048)
    assert crs.epsg is None  # the nested AUTHORITY nodes are not the CRS's code
    # EPSG's own definitions as a LAS 1.4 writer (GDAL) puts them in a file, WKT1 and WKT2
    assert parse_wkt(CRS.from_epsg(32614).to_wkt("WKT1_GDAL")).epsg == 32614
    assert parse_wkt(CRS.from_epsg(4326).to_wkt("WKT2_2019")).is_geographic
    oregon = parse_wkt(CRS.from_epsg(2992).to_wkt("WKT1_GDAL"))  # NAD83 / Oregon GIC Lambert (ft)
    assert (oregon.epsg, oregon.linear_unit, oregon.unit_to_metre) == (2992, "foot", pytest.approx(0.3048))
    # a compound CRS: the horizontal part, the vertical part's unit (NAVD88 height in US survey feet)
    both = parse_wkt(CRS.from_user_input("EPSG:2992+6360").to_wkt("WKT1_GDAL"))
    assert (both.epsg, both.vertical_unit) == (2992, "US survey foot")
    assert both.vertical_to_metre == pytest.approx(1200 / 3937)
    assert parse_wkt("LOCAL_CS[]").kind == "unknown"
    assert parse_wkt('PROJCS["no projection"]').kind == "unknown"  # not a CRS PROJ can read


def test_geokeys_round_trip_and_units():
    keys = {1024: 1, 1025: 1, 3072: 2992, 3076: 9003, 3073: "NAD83 / Oregon", 2057: 6378137.0}
    directory, doubles, ascii_params = encode_geokeys(keys)
    assert parse_geokeys(directory, doubles, ascii_params) == keys
    crs = reference_from_geokeys(keys)
    assert (crs.kind, crs.epsg, crs.linear_unit) == ("projected", 2992, "US survey foot")
    assert crs.unit_to_metre == pytest.approx(1200 / 3937) and crs.vertical_to_metre == crs.unit_to_metre
    # a projected CRS named by its EPSG code only: its unit from PROJ's database (EPSG:2992 is in feet)
    assert reference_from_geokeys({1024: 1, 3072: 2992}).unit_to_metre == pytest.approx(0.3048)
    geo = reference_from_geokeys({1024: 2, 2048: 4326})
    assert geo.is_geographic and geo.vertical_unit == "metre"
    with pytest.raises(InputError, match="declares 3 keys"):
        parse_geokeys([1, 1, 0, 3, 1024, 0, 1, 1])


@pytest.mark.slow
def test_geokeys_for_a_wkt_crs_reads_back_compatible():
    crs = parse_wkt(AUTZEN_WKT)
    back = reference_from_geokeys(geokeys_for(crs))
    assert back.kind == "projected" and back.unit_to_metre == pytest.approx(0.3048)
    check_compatible(crs, back)  # no error


def test_metres_per_degree_matches_reference_values():
    # the series for WGS 84 (e.g. "Geographic coordinate system" in Wikipedia, after Osborne 2008):
    # latitude 111132.92 - 559.82 cos 2p + 1.175 cos 4p - 0.0023 cos 6p, longitude 111412.84 cos p - 93.5 cos 3p
    # + 0.118 cos 5p, metres per degree
    for lat in (0.0, 32.7, 45.0, 60.0):
        p = np.radians(lat)
        m_lat = 111132.92 - 559.82 * np.cos(2 * p) + 1.175 * np.cos(4 * p) - 0.0023 * np.cos(6 * p)
        m_lon = 111412.84 * np.cos(p) - 93.5 * np.cos(3 * p) + 0.118 * np.cos(5 * p)
        assert metres_per_degree(lat) == pytest.approx((m_lat, m_lon), abs=1.0)


def test_local_frame_round_trip_and_transforms():
    crs = CoordinateReference("projected", 2992, "x", "foot", 0.3048, "foot", 0.3048)
    pts = np.array([[636001.5, 848935.2, 406.3], [637179.2, 849497.9, 520.5]])
    frame = LocalFrame.about(pts, crs)
    local = frame.to_local(pts)
    assert np.abs(local).max() < 700  # recentred
    np.testing.assert_allclose(frame.to_file(local), pts, rtol=0, atol=1e-9)
    motion = np.eye(4)
    motion[:2, :2] = [[0, -1], [1, 0]]
    motion[:3, 3] = [5, 6, 7]
    file_t = frame.transform_to_file(motion)
    moved = pts @ file_t[:3, :3].T + file_t[:3, 3]
    np.testing.assert_allclose(frame.to_local(moved), local @ motion[:3, :3].T + motion[:3, 3], atol=1e-6)


def test_check_compatible_refuses_different_crs():
    a = CoordinateReference("projected", 2992, "", "foot", 0.3048, "foot", 0.3048)
    b = CoordinateReference("geographic", 4326, "", "degree", 1.0, "metre", 1.0)
    with pytest.raises(InputError, match="does not reproject"):
        check_compatible(a, b)
