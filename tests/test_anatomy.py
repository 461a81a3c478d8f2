import pytest

from neurowalk import anatomy


def test_actuator_order_is_design_order():
    assert " ".join(anatomy.ACTUATORS) == ("TR1 TR2 TR3 TL1 TL2 TL3 CR1 CR2 CR3 CL1 CL2 CL3 FR1 FR2 FR3 FL1 FL2 FL3 BJ")
    assert anatomy.joint_index("FTi", "L3") == 17 and anatomy.BJ_INDEX == 18
    with pytest.raises(ValueError):
        anatomy.actuator_name("XY", "R1")
