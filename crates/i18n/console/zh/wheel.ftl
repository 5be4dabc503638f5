# 处方表单中患者的方向盘。

wheel-none = 尚未检测到方向盘：限值按设备最大值（训练站会再按其自身方向盘的上限加以限制）。
wheel-line = { $known ->
    [no] 方向盘：{ $model }，额定 { $rated }，有效上限 { $ceiling }（训练站不认识的型号：力量保持在较低水平）。
   *[yes] 方向盘：{ $model }，额定 { $rated }，有效上限 { $ceiling }。
}
