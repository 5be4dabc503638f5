# 练习前在被忽略一侧的提示。
neglect-look-here = 请看这边。
