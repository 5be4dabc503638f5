# 控制台外壳：页面标题、页眉、导航、语言菜单、登录、密码、患者页的标签、错误。

app-title = telerehab — 治疗师控制台
app-loading = 正在加载…
app-nav =
    .aria-label = 主菜单
app-nav-clinic = 诊所
app-nav-names = 姓名
app-nav-audit = 审计日志
app-nav-change-password = 修改密码
app-nav-logout = 退出登录
app-language-label = 语言
app-who = { $email }（{ $role ->
        [admin] 管理员
       *[other] 治疗师
    }）
app-back-to-patients = 返回患者列表

## 登录

app-login-title = 登录
app-login-email = 电子邮箱
app-login-password = 密码
app-login-submit = 登录

## 密码

app-password-title = 修改密码
app-password-title-forced = 设置您自己的密码
app-password-forced = 您使用一次性密码登录。请先设置您自己的密码再继续。
app-password-one-time = 一次性密码
app-password-current = 当前密码
app-password-new = 新密码
app-password-rules = （至少 10 个字符，不能只有空格，不能是您的电子邮箱，不能是常见密码或规律组合；最好用几个互不相关的词）
app-password-repeat = 再次输入新密码
app-password-submit = 修改密码
app-password-differ = 两次输入的新密码不一致。

## 患者页

app-patient-title = 患者 { $name }
app-tabs-label = 患者
app-tab-live = 实时
app-tab-progress = 进展
app-tab-replay = 回放
app-tab-prescribe = 处方
app-tab-exercises = 练习
app-tab-stations = 训练站与配对
