#!/usr/bin/env python3
"""A serial chain of N revolute links as a URDF (issue 54's long chains): the joint axes
alternate z, y, x, each joint 0.1 m above the last along the parent's z, each link 1 kg with
its centre 0.05 m up its z (and 0.01 m off along x) and a full inertia tensor (products of
inertia included), joint limits +-3 rad. Usage, from the repository root:

    python3 benches/scale/serial_chain.py N > chainN.urdf
    target/release/mechanism import chainN.urdf -o chainN.mech
    target/release/mechanism equations chainN.mech

`benches/baselines/pinocchio/chain_fixture.py` builds the same URDF (it imports `urdf` from
here) for the Pinocchio fixture of the 200-link chain.
"""

import sys

AXES = ["0 0 1", "0 1 0", "1 0 0"]


def urdf(n):
    """The URDF text of the chain of `n` moving links below a fixed base link."""
    out = [f'<?xml version="1.0"?>', f'<robot name="chain{n}">', '  <link name="base"/>']
    for i in range(1, n + 1):
        parent = "base" if i == 1 else f"link{i - 1}"
        out += [
            f'  <link name="link{i}">',
            "    <inertial>",
            '      <origin xyz="0.01 0 0.05" rpy="0 0 0"/>',
            '      <mass value="1"/>',
            '      <inertia ixx="0.0042" ixy="0.0001" ixz="-0.0002" iyy="0.0041" iyz="0.0003" izz="0.0008"/>',
            "    </inertial>",
            "  </link>",
            f'  <joint name="j{i}" type="revolute">',
            f'    <parent link="{parent}"/>',
            f'    <child link="link{i}"/>',
            f'    <origin xyz="0 0 {0.0 if i == 1 else 0.1}" rpy="0 0 0"/>',
            f'    <axis xyz="{AXES[(i - 1) % 3]}"/>',
            '    <limit lower="-3" upper="3" effort="100" velocity="10"/>',
            "  </joint>",
        ]
    out.append("</robot>")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    sys.stdout.write(urdf(int(sys.argv[1])))
