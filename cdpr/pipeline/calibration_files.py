"""The files of a calibration, written atomically (``cdpr.io.atomic``: a file appears complete or
not at all, with the mode a plain ``open()`` gives it): the data table (``write_data``, the CSV
``cdpr.analyses.calibration.read_data`` reads) and the calibrated robot (``write_robot``, the file
``cdpr calibrate fit --out`` writes, from commanded lengths or motor angles). The analyses layer computes their content
(``calibration.data_frame``, ``calibration.robot_file_text``) and writes nothing itself."""

from __future__ import annotations

import datetime

import yaml

from cdpr import io
from cdpr.analyses.calibration import data_frame, robot_file_text
from cdpr.errors import ConfigError

#: Digits of the data table's floats: every float64 round-trips (the table is an input again).
DATA_FORMAT = "%.17g"


def write_data(path, data, robot):
    """Write ``data`` as a calibration CSV (the format ``calibration.read_data`` reads).

    Parameters
    ----------
    path : str or Path
        The .csv file; its folder is created.
    data : calibration.Data
    robot : Robot
        Fixes the columns (``calibration.data_frame``).

    Returns
    -------
    None
    """
    df = data_frame(data, robot)
    io.atomic(path, lambda tmp: df.to_csv(tmp, index=False, float_format=DATA_FORMAT))


def write_robot(path, cal, data_source, when=None):
    """Write the calibrated robot file of a fit (``calibration.robot_file_text``: the input's
    schema, per-cable plain SI values, or for a motor-angle fit the nominal robot file with the
    estimated anchors and spools; a header naming the data, the model and the time).

    Parameters
    ----------
    path : str or Path
        The .yaml file; its folder is created.
    cal : calibration.Calibration or calibration.MotorCalibration
    data_source : str
        The data file named in the header.
    when : datetime.datetime, optional
        The time named in the header (default now, UTC).

    Returns
    -------
    None
    """
    if when is None:
        when = datetime.datetime.now(datetime.timezone.utc)
    io.write_text(robot_file_text(cal, data_source, when), path)


def read_study_file(path):
    """The mapping of a calibration study file (``config/studies/calibration*.yaml``,
    ``hangprinter.yaml``), or ConfigError in one line naming the file: it does not exist, is not
    YAML, or is not a mapping of keys to values.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict
    """
    try:
        with open(path, encoding="utf-8") as f:
            data = yaml.safe_load(f)
    except FileNotFoundError:
        raise ConfigError(path, None, "the study file does not exist") from None
    except yaml.YAMLError as e:
        raise ConfigError(path, None, f"not valid YAML ({str(e).splitlines()[0]})") from None
    if not isinstance(data, dict):
        raise ConfigError(path, None, "expected a mapping of keys to values")
    return data
